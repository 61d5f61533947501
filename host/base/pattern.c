/* Frame patterns in output file names: see pattern.h. */
#include "base/pattern.h"

#include <stdio.h>
#include <string.h>

#include "base/util.h"

/* The conversion at s (s[0] == '%', not "%%"): its length and width (0: none), or 0 when
 * it is not %d / %0Nd. */
static size_t conversion(const char *s, int *width)
{
    size_t i = 1;
    *width = 0;
    if (s[i] == '0') {
        i++;
        size_t d = 0;
        while (s[i] >= '0' && s[i] <= '9' && d < 9) {
            *width = *width * 10 + (s[i] - '0');
            i++, d++;
        }
        if (d == 0 || *width == 0)
            return 0;
    }
    return s[i] == 'd' ? i + 1 : 0;
}

int lg_frame_pattern_scan(const char *path, size_t *pos, char *why, size_t why_len)
{
    int found = 0;
    size_t first = 0;
    for (size_t i = 0; path[i]; i++) {
        if (path[i] != '%')
            continue;
        if (path[i + 1] == '%') {
            i++;
            continue;
        }
        int width;
        size_t len = conversion(path + i, &width);
        *pos = i;
        if (!len) {
            if (why) {
                /* the conversion as written, up to its letter (at most 12 characters) */
                size_t n = 1;
                while (path[i + n] && n < 12 && !strchr("diouxXeEfFgGaAcspn%", path[i + n]))
                    n++;
                if (path[i + n] && path[i + n] != '%' && n < 12)
                    n++;
                snprintf(why, why_len,
                         "'%.*s' is not a frame number: use %%d or %%0Nd (N from 1 to 9; "
                         "%%%% for a '%%')",
                         (int)n, path + i);
            }
            return -1;
        }
        if (found) {
            if (why)
                snprintf(why, why_len,
                         "a second frame number (the first is at character %zu): a name "
                         "holds at most one",
                         first + 1);
            return -1;
        }
        found = 1;
        first = i;
        i += len - 1;
    }
    return found;
}

char *lg_frame_pattern_name(const char *path, uint32_t frame)
{
    size_t pos;
    if (lg_frame_pattern_scan(path, &pos, NULL, 0) != 1)
        return lg_xstrdup(path);
    lg_str out = { 0 };
    for (size_t i = 0; path[i]; i++) {
        if (path[i] != '%') {
            lg_str_addc(&out, path[i]);
            continue;
        }
        if (path[i + 1] == '%') {
            lg_str_addc(&out, '%');
            i++;
            continue;
        }
        int width;
        size_t len = conversion(path + i, &width);
        lg_str_addf(&out, "%0*u", width, frame);
        i += len - 1;
    }
    return lg_str_take(&out);
}
