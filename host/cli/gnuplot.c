/* gnuplot run on a script and its data, for sweep's and tune's plots (commands.h). */
#include "cli/commands.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static const char *base_name(const char *p)
{
    const char *slash = strrchr(p, '/');
    return slash ? slash + 1 : p;
}

int lg_run_gnuplot(const char *dir, const char *gp, const char *csv, const char *png)
{
    char *vars = lg_xasprintf("data='%s'; out='%s'", base_name(csv), base_name(png));
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) {
        free(vars);
        return -1;
    }
    if (pid == 0) {
        if (chdir(dir) != 0)
            _exit(127);
        execlp("gnuplot", "gnuplot", "-e", vars, base_name(gp), (char *)NULL);
        _exit(127);
    }
    free(vars);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? 0 : -1;
}
