/*
 * lightgraph/file.h: the rules every loader reads by. Special files are refused at once,
 * never read (a FIFO without a writer, /dev/zero, a directory); sizes are checked before a
 * byte is read; confined reads refuse "../" and symbolic links that lead out of the folder,
 * and accept links that stay inside it.
 */
#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "codectest.h"
#include "lightgraph/file.h"

static char dir[4096];

static const char *at(const char *name)
{
    static char buf[4][4200];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
    return buf[k];
}

static void put(const char *name, const char *text)
{
    FILE *f = fopen(at(name), "wb");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

int main(void)
{
    snprintf(dir, sizeof dir, "%s", make_scratch("file"));
    char err[512];
    size_t len = 0;

    /* a regular file, whole, with its NUL */
    put("a.txt", "hello");
    char *s = lg_file_read(at("a.txt"), 5, &len, err, sizeof err);
    CHECKF(s && len == 5 && strcmp(s, "hello") == 0, "read a.txt: %s", s ? s : err);
    free(s);
    /* one byte over the limit: refused before reading, sizes named */
    s = lg_file_read(at("a.txt"), 4, &len, err, sizeof err);
    CHECKF(!s && errno == EFBIG && strstr(err, "5 bytes, over the 4 bytes limit"), "limit: %s",
           err);
    /* empty */
    put("e.txt", "");
    s = lg_file_read(at("e.txt"), 0, &len, err, sizeof err);
    CHECKF(s && len == 0 && s[0] == 0, "empty: %s", err);
    free(s);
    /* missing */
    s = lg_file_read(at("nope"), 10, &len, err, sizeof err);
    CHECKF(!s && errno == ENOENT && strstr(err, "No such file"), "missing: %s", err);

    /* special files: refused at once, named */
    CHECK(mkfifo(at("f.fifo"), 0600) == 0);
    s = lg_file_read(at("f.fifo"), 100, &len, err, sizeof err);
    CHECKF(!s && strstr(err, "it is a FIFO, not a regular file"), "fifo: %s", err);
    s = lg_file_read("/dev/zero", 1u << 30, &len, err, sizeof err);
    CHECKF(!s && strstr(err, "it is a character device"), "/dev/zero: %s", err);
    s = lg_file_read(dir, 1u << 30, &len, err, sizeof err);
    CHECKF(!s && errno == EISDIR && strstr(err, "it is a directory"), "dir: %s", err);
    uint64_t size = 0;
    int fd = lg_file_open(at("a.txt"), 100, &size, err, sizeof err);
    CHECKF(fd >= 0 && size == 5, "open: %s", err);
    if (fd >= 0) {
        CHECK((fcntl(fd, F_GETFL) & O_NONBLOCK) == 0); /* blocking again for codecs */
        CHECK((fcntl(fd, F_GETFD) & FD_CLOEXEC) != 0);
        close(fd);
    }

    /* confinement: model/ holds b.bin and a link to it; ../a.txt, /etc/passwd and a link to
     * the parent's a.txt lead out */
    CHECK(mkdir(at("model"), 0700) == 0);
    CHECK(mkdir(at("model/sub"), 0700) == 0);
    put("model/b.bin", "bytes");
    CHECK(symlink("b.bin", at("model/in.bin")) == 0);
    CHECK(symlink("../a.txt", at("model/out.bin")) == 0);
    CHECK(symlink("..", at("model/up")) == 0);
    char root[4200];
    snprintf(root, sizeof root, "%s", at("model"));
    s = lg_file_read_within(root, "b.bin", 100, &len, err, sizeof err);
    CHECKF(s && len == 5, "inside: %s", err);
    free(s);
    s = lg_file_read_within(root, "sub/../in.bin", 100, &len, err, sizeof err);
    CHECKF(s && len == 5, "link inside: %s", err);
    free(s);
    s = lg_file_read_within(root, at("model/b.bin"), 100, &len, err, sizeof err);
    CHECKF(s && len == 5, "absolute inside: %s", err);
    free(s);
    static const char *const escapes[] = { "../a.txt", "out.bin", "up/a.txt",
                                           "../../../../../../../../etc/passwd", "/etc/passwd" };
    for (int i = 0; i < 5; i++) {
        s = lg_file_read_within(root, escapes[i], 1u << 20, &len, err, sizeof err);
        CHECKF(!s && errno == EACCES && strstr(err, "outside") && strstr(err, escapes[i]), "%s: %s",
               escapes[i], s ? "read" : err);
        free(s);
        CHECKF(lg_path_within(root, escapes[i], err, sizeof err) != 0 && strstr(err, "outside"),
               "path_within %s: %s", escapes[i], err);
    }
    CHECKF(lg_path_within(root, "in.bin", err, sizeof err) == 0, "path_within in.bin: %s", err);
    CHECKF(lg_path_within(root, "sub", err, sizeof err) == 0, "path_within sub: %s", err);
    /* a root that is itself a link: what is inside its target is inside */
    CHECK(symlink("model", at("model-link")) == 0);
    s = lg_file_read_within(at("model-link"), "b.bin", 100, &len, err, sizeof err);
    CHECKF(s && len == 5, "linked root: %s", err);
    free(s);
    /* a sibling folder whose name extends the root's is not inside it */
    CHECK(mkdir(at("model2"), 0700) == 0);
    put("model2/c.bin", "x");
    s = lg_file_read_within(root, "../model2/c.bin", 100, &len, err, sizeof err);
    CHECKF(!s && strstr(err, "outside"), "sibling: %s", err);
    /* confined and special: still refused as special, without hanging */
    CHECK(mkfifo(at("model/g.fifo"), 0600) == 0);
    s = lg_file_read_within(root, "g.fifo", 100, &len, err, sizeof err);
    CHECKF(!s && strstr(err, "FIFO"), "confined fifo: %s", err);

    return check_report_scratch("file", dir);
}
