/* Start values of parameters from resources/start_values.txt (start_values.h). */
#include <errno.h>
#include <locale.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "start_values.h"

#define PATH_LEN 4096
#define LINE_LEN 512

static int hex_digit(int ch) {
    if (ch >= '0' && ch <= '9') return ch - '0';
    if (ch >= 'a' && ch <= 'f') return ch - 'a' + 10;
    if (ch >= 'A' && ch <= 'F') return ch - 'A' + 10;
    return -1;
}

/* The native path of the file URI `uri` (file:///p, file:/p, file://localhost/p; %XX decoded; a
 * Windows drive /C:/p as C:/p). 0 when it is not a file URI or does not fit in n bytes. */
static int uri_path(const char *uri, char *out, size_t n) {
    const char *s;
    size_t k = 0;
    if (strncmp(uri, "file:", 5) != 0) return 0;
    s = uri + 5;
    if (strncmp(s, "///", 3) == 0) s += 2;
    else if (strncmp(s, "//localhost/", 12) == 0) s += 11;
    else if (strncmp(s, "//", 2) == 0) return 0;          /* another host */
    if (s[0] == '/' && s[1] && s[2] == ':' && ((s[1] >= 'A' && s[1] <= 'Z') || (s[1] >= 'a' && s[1] <= 'z')))
        s++;
    for (; *s; s++) {
        int ch = (unsigned char)*s;
        if (ch == '%') {
            int hi = hex_digit((unsigned char)s[1]), lo = hi < 0 ? -1 : hex_digit((unsigned char)s[2]);
            if (hi < 0 || lo < 0) return 0;
            ch = hi * 16 + lo;
            s += 2;
        }
        if (k + 1 >= n) return 0;
        out[k++] = (char)ch;
    }
    out[k] = '\0';
    return 1;
}

/* the full path of the start-value file in the resource folder `location`; 0 if it does not fit */
static int file_path(const char *location, int is_uri, char *out, size_t n) {
    size_t len;
    if (is_uri) {
        if (!uri_path(location, out, n)) return 0;
    } else {
        if (strlen(location) + 1 > n) return 0;
        strcpy(out, location);
    }
    len = strlen(out);
    if (len > 0 && out[len - 1] != '/' && out[len - 1] != '\\') {
        if (len + 2 > n) return 0;
        out[len++] = '/';
        out[len] = '\0';
    }
    if (len + strlen(START_VALUES_FILE) + 1 > n) return 0;
    strcpy(out + len, START_VALUES_FILE);
    return 1;
}

/* a decimal number with '.' as its point whatever the C locale of the process; 0 if `text` is
 * not one number */
static int parse_number(const char *text, double *value) {
    char buf[LINE_LEN];
    char *end;
    const char *point = localeconv()->decimal_point;
    size_t k, len = strlen(text);
    if (len == 0 || len >= sizeof buf) return 0;
    for (k = 0; k <= len; k++) {
        char ch = text[k];
        if (ch == ',' ) return 0;
        buf[k] = (ch == '.' && point && point[0] && point[1] == '\0') ? point[0] : ch;
    }
    errno = 0;
    *value = strtod(buf, &end);
    return end != buf && *end == '\0' && errno != ERANGE;
}

static int find_row(const char *name) {
    int j;
    for (j = 0; j < MODEL_NVARS; j++)
        if (strcmp(MODEL_VARS[j].name, name) == 0) return j;
    return -1;
}

#define BAD(...) do { fmu_log(c, fmi2Error, LOG_ERROR, __VA_ARGS__); fclose(f); return 0; } while (0)

static int read_file(instance_t *c, FILE *f, const char *path) {
    char line[LINE_LEN];
    int lineno = 0;
    while (fgets(line, sizeof line, f)) {
        char name[LINE_LEN], text[LINE_LEN], rest[2];
        const model_var_t *v;
        double value;
        int row, got;
        lineno++;
        if (!strchr(line, '\n') && !feof(f))
            BAD("%s line %d: longer than %d characters", path, lineno, LINE_LEN - 2);
        got = sscanf(line, " %511s %511s %1s", name, text, rest);
        if (got <= 0 || name[0] == '#') continue;
        if (got == 3 && rest[0] == '#') got = 2;               /* a comment after the value */
        if (got != 2)
            BAD("%s line %d: expected \"name value\", got %d fields", path, lineno, got == 1 ? 1 : 3);
        if ((row = find_row(name)) < 0) BAD("%s line %d: %s is not a variable of this FMU", path, lineno, name);
        v = &MODEL_VARS[row];
        if (v->causality != 'p') BAD("%s line %d: %s is not a parameter (only parameters have start values "
                                     "here)", path, lineno, name);
        if (v->type == 'B') {
            if (strcmp(text, "true") == 0 || strcmp(text, "1") == 0) value = 1.0;
            else if (strcmp(text, "false") == 0 || strcmp(text, "0") == 0) value = 0.0;
            else BAD("%s line %d: %s = %s: allowed true or false", path, lineno, name, text);
        } else {
            if (!parse_number(text, &value) || !isfinite(value))
                BAD("%s line %d: %s = %s: allowed a finite number ('.' as the decimal point)", path, lineno,
                    name, text);
            if (v->type == 'I' && value != floor(value))
                BAD("%s line %d: %s = %s: allowed an integer", path, lineno, name, text);
            if (value < v->min || value > v->max)
                BAD("%s line %d: %s = %s: allowed [%.17g, %.17g]", path, lineno, name, text, v->min, v->max);
        }
        c->m.val[v->vr] = value;
    }
    if (ferror(f)) BAD("%s: read error after line %d", path, lineno);
    fclose(f);
    return 1;
}

int model_load_start_values(instance_t *c, const char *location, int is_uri) {
    char path[PATH_LEN], msg[512];
    plant_params_t p;
    FILE *f;
    if (location && *location) {
        if (!file_path(location, is_uri, path, sizeof path)) {
            /* not on this machine's file system: the resources cannot be read, so none are */
            fmu_log(c, fmi2Warning, LOG_WARNING, "resource location %s: not a local file URI of at most %d bytes: "
                    "resources/" START_VALUES_FILE " is not read (the FMU starts from its built-in start values)",
                    location, PATH_LEN - 1);
            goto keep;
        }
        f = fopen(path, "r");
        if (f) {
            if (!read_file(c, f, path)) return 0;
            if (!params_compile(c->m.val, &p, msg, sizeof msg)) {
                fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s", path, msg);
                return 0;
            }
            c->m.tol = c->m.val[VR_solver_tol];
        } else if (errno != ENOENT) {
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: cannot be read (%s)", path, strerror(errno));
            return 0;
        }
    }
keep:
    memcpy(c->start_val, c->m.val, sizeof c->start_val);
    return 1;
}

void model_reset(instance_t *c) {
    model_defaults(&c->m);
    memcpy(c->m.val, c->start_val, sizeof c->start_val);
    c->m.tol = c->m.val[VR_solver_tol];
}
