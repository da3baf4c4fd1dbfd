/* SPDX-License-Identifier: MIT */
/*
** replay.c -- runs a fuzz target without libFuzzer: every file named on
** the command line, and every file in every directory named, is passed
** once to LLVMFuzzerTestOneInput.  "make check" builds each target with
** it (any compiler, the suite's flags, also under make sanitize) and
** replays fuzz/corpus/<target> and fuzz/crashes/<target>, so every
** committed input stays a regression test.  A broken contract aborts.
*/
#include <dirent.h>
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "fuzz.h"

/* Run the target on one file; 0, or -1 if it cannot be read. */
static int replay_file(const char *path)
{
    FILE *fp = fopen(path, "rb");
    uint8_t *data = NULL;
    size_t size = 0, cap = 0;
    int failed;

    if (fp == NULL) {
        fprintf(stderr, "replay: %s: %s\n", path, strerror(errno));
        return -1;
    }
    failed = 0;
    for (;;) {
        size_t got;
        if (size == cap) {
            size_t ncap = cap ? 2 * cap : 4096;
            uint8_t *p = (uint8_t *)realloc(data, ncap);
            if (p == NULL) {
                failed = 1;
                break;
            }
            data = p;
            cap = ncap;
        }
        got = fread(data + size, 1, cap - size, fp);
        size += got;
        if (got == 0)
            break;
    }
    failed |= ferror(fp);
    fclose(fp);
    if (failed) {
        fprintf(stderr, "replay: %s: cannot read\n", path);
        free(data);
        return -1;
    }
    LLVMFuzzerTestOneInput(data, size);
    free(data);
    return 0;
}

/* Run every regular file in "dir" (not recursive); count them in *n. */
static int replay_dir(const char *dir, unsigned long *n)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int rc = 0;

    if (d == NULL) {
        fprintf(stderr, "replay: %s: %s\n", dir, strerror(errno));
        return -1;
    }
    while (rc == 0 && (e = readdir(d)) != NULL) {
        char path[4096];
        struct stat st;
        if (e->d_name[0] == '.')
            continue;
        if ((size_t)snprintf(path, sizeof path, "%s/%s", dir, e->d_name) >=
            sizeof path)
            rc = -1;
        else if (stat(path, &st) == 0 && S_ISREG(st.st_mode)) {
            rc = replay_file(path);
            ++*n;
        }
    }
    closedir(d);
    return rc;
}

int main(int argc, char **argv)
{
    const char *name = strrchr(argv[0], '/') ? strrchr(argv[0], '/') + 1
                                              : argv[0];
    unsigned long n = 0;
    int i;

    for (i = 1; i < argc; i++) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            /* A target may have no reproducers yet: nothing to replay. */
            if (errno == ENOENT)
                continue;
            fprintf(stderr, "replay: %s: %s\n", argv[i], strerror(errno));
            return 1;
        }
        if (S_ISDIR(st.st_mode) ? replay_dir(argv[i], &n) != 0
                                : (n++, replay_file(argv[i]) != 0))
            return 1;
    }
    printf("replay: %s: %lu inputs\n", name, n);
    return 0;
}
