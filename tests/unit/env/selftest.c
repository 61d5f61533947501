/* The guard's own test: a thread, then setenv. Under envguard this must abort; without it,
 * it exits 0. test_env.sh checks both, so the guard is known to catch the write. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>

static void *worker(void *arg)
{
    return arg;
}

int main(void)
{
    if (setenv("LG_ENVGUARD_BEFORE", "1", 1)) /* before any thread: allowed */
        return 1;
    pthread_t t;
    if (pthread_create(&t, NULL, worker, NULL))
        return 1;
    pthread_join(t, NULL);
    /* the same value again: glibc swaps one entry's pointer, environ stays; tolerated */
    if (setenv("LG_ENVGUARD_BEFORE", "1", 1))
        return 1;
    setenv("LG_ENVGUARD_AFTER", "1", 1); /* after: the guard aborts here */
    puts("setenv after a thread returned");
    return 0;
}
