/* SPDX-License-Identifier: MIT */
/*
** amalgamate.c -- writes libray's one-file build (make amalgamation):
** every source file given, in order, with the private headers they
** include inlined where they are first included (once), as SQLite's
** amalgamation is made.  The sources stay as they are; what one
** translation unit needs that forty do not is done here:
**
**   * A file's own file-scope names (static functions and variables,
**     typedefs, struct/union/enum tags, enum constants) that another
**     source file or any private header also spells are renamed in that
**     file, prefixed with its path (src/query/closest.c's "max2" becomes
**     "query_closest__max2"): two files' max2 or split no longer meet.  An
**     identifier after "." or "->" (a member) or "#" (a directive) is
**     left alone, and so are names in the library's namespace (ray_*,
**     RAY_*), which are unique.
**   * The macros a source file defines are #undef'd after it, so that
**     BINS or CHUNK of one file is not seen by the next; one that a
**     header also defines (for its own files) is renamed in the file.
**   * The library's internal functions (ray__*, not static: they are
**     called across files) that a header declares by name (not through
**     a macro) are declared and defined RAY__STATIC, which
**     the prologue makes "static" (the unused ones are dropped) unless
**     RAY_AMALGAMATION_INTERNALS is defined (the project's own tests
**     link them).
**   * A file given with -if FILE COND is wrapped in #if COND / #endif
**     (src/image/png.c: RAY_PNG), the private headers it includes being
**     inlined before the #if, so that files after it still see them.
**
** It reads C as tokens (comments, strings, character constants,
** preprocessor lines), not as text, so nothing in a string or a comment
** is renamed.  It parses only the file-scope declarations it needs (the
** first names they declare); names made by ## (scene/kinds.c's X-macros)
** are not seen, and a clash among those shows as a compile error of the
** amalgamation in make check, as would any other thing this misses.
**
** Usage: amalgamate -o OUT -I SRCDIR [-p PROLOGUE] [-if FILE COND]...
**                   FILE.c...
** PROLOGUE is copied first (libray's switches and pragmas,
** scripts/amalgamation-prologue.h).  Private headers are the quoted
** includes found under SRCDIR; any other include line is kept as it is.
** Exit status 0, or 1 with a message on stderr.
*/
#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------ utilities */

#if defined(__GNUC__)
#define PRINTF_LIKE __attribute__((format(printf, 1, 2)))
#else
#define PRINTF_LIKE
#endif

static void die(const char *fmt, ...) PRINTF_LIKE;

static void die(const char *fmt, ...)
{
    va_list ap;

    fputs("amalgamate: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    exit(1);
}

static void *xmalloc(size_t n)
{
    void *p = malloc(n ? n : 1);

    if (p == NULL)
        die("out of memory");
    return p;
}

static void *xrealloc(void *p, size_t n)
{
    p = realloc(p, n ? n : 1);
    if (p == NULL)
        die("out of memory");
    return p;
}

static char *xstrndup(const char *s, size_t n)
{
    char *d = xmalloc(n + 1);

    memcpy(d, s, n);
    d[n] = '\0';
    return d;
}

static char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    char *text = NULL;
    size_t len = 0, cap = 0, got;

    if (f == NULL)
        return NULL;
    do {
        if (cap - len < 65536) {
            cap = cap * 2 + 65536;
            text = xrealloc(text, cap + 1);
        }
        got = fread(text + len, 1, cap - len, f);
        len += got;
    } while (got > 0);
    if (ferror(f))
        die("cannot read %s", path);
    fclose(f);
    text[len] = '\0';
    return text;
}

/* A set of names: open addressing over FNV-1a, never shrunk. */
typedef struct name_set {
    char **slot;
    size_t cap, count;
} name_set;

static size_t hash_name(const char *s, size_t n)
{
    size_t h = 2166136261u, i;

    for (i = 0; i < n; i++)
        h = (h ^ (unsigned char)s[i]) * 16777619u;
    return h;
}

static char **set_slot(const name_set *set, const char *s, size_t n)
{
    size_t i = hash_name(s, n) & (set->cap - 1);

    while (set->slot[i] != NULL &&
           !(strlen(set->slot[i]) == n && memcmp(set->slot[i], s, n) == 0))
        i = (i + 1) & (set->cap - 1);
    return &set->slot[i];
}

static int set_has(const name_set *set, const char *s, size_t n)
{
    return set->cap > 0 && *set_slot(set, s, n) != NULL;
}

static void set_add(name_set *set, const char *s, size_t n)
{
    char **slot;

    if (2 * (set->count + 1) > set->cap) {
        name_set bigger;
        size_t i;

        bigger.cap = set->cap ? 2 * set->cap : 256;
        bigger.count = set->count;
        bigger.slot = xmalloc(bigger.cap * sizeof *bigger.slot);
        memset(bigger.slot, 0, bigger.cap * sizeof *bigger.slot);
        for (i = 0; i < set->cap; i++)
            if (set->slot[i] != NULL)
                *set_slot(&bigger, set->slot[i], strlen(set->slot[i])) =
                    set->slot[i];
        free(set->slot);
        *set = bigger;
    }
    slot = set_slot(set, s, n);
    if (*slot == NULL) {
        *slot = xstrndup(s, n);
        set->count++;
    }
}

/* ------------------------------------------------------------- tokens */

enum tok_kind { T_IDENT, T_NUMBER, T_STRING, T_PUNCT };

/* A token of a file's text: where it starts and ends; pp: inside a
** preprocessor directive, whose first token ("#") has pp_start set. */
typedef struct token {
    enum tok_kind kind;
    size_t at, len;
    int pp, pp_start;
} token;

typedef struct source {
    char *path;                 /* as given or as found under SRCDIR */
    char *text;
    token *tok;
    size_t ntok;
    int header;
} source;

static int tok_is(const source *f, size_t i, const char *s)
{
    size_t n = strlen(s);

    return i < f->ntok && f->tok[i].len == n &&
           memcmp(f->text + f->tok[i].at, s, n) == 0;
}

static int ident_char(int c)
{
    return isalnum(c) || c == '_';
}

/* The text's tokens; comments and white space are between them. */
static void tokenize(source *f)
{
    const char *s = f->text;
    size_t i = 0, cap = 0;
    int in_pp = 0, line_start = 1;

    f->tok = NULL;
    f->ntok = 0;
    while (s[i] != '\0') {
        token t;
        char c = s[i];

        if (c == '\n') {
            in_pp = 0;
            line_start = 1;
            i++;
            continue;
        }
        if (c == '\\' && s[i + 1] == '\n') {        /* line splice */
            i += 2;
            continue;
        }
        if (isspace((unsigned char)c)) {
            i++;
            continue;
        }
        if (c == '/' && s[i + 1] == '*') {
            const char *end = strstr(s + i + 2, "*/");
            if (end == NULL)
                die("%s: unterminated comment", f->path);
            i = (size_t)(end - s) + 2;
            continue;
        }
        if (c == '/' && s[i + 1] == '/') {
            while (s[i] != '\0' && s[i] != '\n')
                i++;
            continue;
        }
        t.at = i;
        t.pp_start = 0;
        if (c == '#' && line_start) {
            in_pp = 1;
            t.pp_start = 1;
        }
        line_start = 0;
        t.pp = in_pp;
        if (isalpha((unsigned char)c) || c == '_') {
            while (ident_char((unsigned char)s[i]))
                i++;
            t.kind = T_IDENT;
        } else if (isdigit((unsigned char)c) ||
                   (c == '.' && isdigit((unsigned char)s[i + 1]))) {
            while (ident_char((unsigned char)s[i]) || s[i] == '.' ||
                   ((s[i] == '+' || s[i] == '-') &&
                    strchr("eEpP", s[i - 1]) != NULL))
                i++;
            t.kind = T_NUMBER;
        } else if (c == '"' || c == '\'') {
            i++;
            while (s[i] != c) {
                if (s[i] == '\n' && in_pp)
                    break;  /* an unpaired quote in #error text */
                if (s[i] == '\0' || s[i] == '\n')
                    die("%s: unterminated %s", f->path,
                        c == '"' ? "string" : "character constant");
                i += s[i] == '\\' ? 2 : 1;
            }
            if (s[i] == c)
                i++;
            t.kind = T_STRING;
        } else if (c == '-' && s[i + 1] == '>') {
            i += 2;
            t.kind = T_PUNCT;
        } else if (c == '#' && s[i + 1] == '#') {
            i += 2;
            t.kind = T_PUNCT;
        } else {
            i++;
            t.kind = T_PUNCT;
        }
        t.len = i - t.at;
        if (f->ntok == cap) {
            cap = cap * 2 + 1024;
            f->tok = xrealloc(f->tok, cap * sizeof *f->tok);
        }
        f->tok[f->ntok++] = t;
    }
}

/* The directive starting at token i ("#"): its name's token, or ntok. */
static size_t directive_name(const source *f, size_t i)
{
    return i + 1 < f->ntok && f->tok[i + 1].pp && !f->tok[i + 1].pp_start
               ? i + 1
               : f->ntok;
}

/* The token after the directive that starts at token i. */
static size_t directive_end(const source *f, size_t i)
{
    i++;
    while (i < f->ntok && f->tok[i].pp && !f->tok[i].pp_start)
        i++;
    return i;
}

/* ------------------------------------------------- file-scope names */

static const char *const keywords[] = {
    "auto", "break", "case", "char", "const", "continue", "default", "do",
    "double", "else", "enum", "extern", "float", "for", "goto", "if",
    "inline", "int", "long", "register", "restrict", "return", "short",
    "signed", "sizeof", "static", "struct", "switch", "typedef", "union",
    "unsigned", "void", "volatile", "while", "_Bool", "_Complex",
    "__attribute__", "__inline", "__inline__", "__restrict", "__extension__",
    NULL
};

static int is_keyword(const source *f, size_t i)
{
    int k;

    for (k = 0; keywords[k] != NULL; k++)
        if (tok_is(f, i, keywords[k]))
            return 1;
    return 0;
}

/* What the parse finds in one file. */
typedef struct names {
    name_set locals;        /* file-scope names private to the file */
    name_set externs;       /* functions defined here, not static */
    name_set macros;        /* macros it #defines */
    name_set function_macros;
    size_t *decl_start;     /* first token of each ray__ declaration */
    char **decl_name;
    size_t ndecl, cap;
} names;

/* The next token at or after i that is not in a directive. */
static size_t code(const source *f, size_t i)
{
    while (i < f->ntok && f->tok[i].pp)
        i++;
    return i;
}

/* From the opening bracket at i to the token after its match. */
static size_t skip_balanced(const source *f, size_t i)
{
    int depth = 0;

    for (; i < f->ntok; i = code(f, i + 1)) {
        const char *p = f->text + f->tok[i].at;
        if (f->tok[i].kind != T_PUNCT)
            continue;
        if (*p == '(' || *p == '[' || *p == '{')
            depth++;
        else if (*p == ')' || *p == ']' || *p == '}') {
            if (--depth == 0)
                return code(f, i + 1);
        }
    }
    die("%s: unbalanced brackets", f->path);
    return i;
}

static void add_name(const source *f, name_set *set, size_t i)
{
    set_add(set, f->text + f->tok[i].at, f->tok[i].len);
}

static void note_decl(names *nm, const source *f, size_t start, size_t name)
{
    if (nm->ndecl == nm->cap) {
        nm->cap = nm->cap * 2 + 64;
        nm->decl_start = xrealloc(nm->decl_start,
                                  nm->cap * sizeof *nm->decl_start);
        nm->decl_name = xrealloc(nm->decl_name,
                                 nm->cap * sizeof *nm->decl_name);
    }
    nm->decl_start[nm->ndecl] = start;
    nm->decl_name[nm->ndecl] =
        xstrndup(f->text + f->tok[name].at, f->tok[name].len);
    nm->ndecl++;
}

/* A struct, union or enum specifier at i (the keyword): its tag, if the
** specifier has a body, is a name of the file; an enum's constants too.
** Returns the token after the specifier. */
static size_t specifier(const source *f, size_t i, names *nm)
{
    int is_enum = tok_is(f, i, "enum");
    size_t tag = f->ntok;

    i = code(f, i + 1);
    if (i < f->ntok && f->tok[i].kind == T_IDENT) {
        tag = i;
        i = code(f, i + 1);
    }
    if (!tok_is(f, i, "{"))
        return i;
    if (tag < f->ntok)
        add_name(f, &nm->locals, tag);
    if (is_enum) {
        size_t j = code(f, i + 1);
        int expect = 1, depth = 0;

        for (; j < f->ntok; j = code(f, j + 1)) {
            const char *p = f->text + f->tok[j].at;
            if (f->tok[j].kind == T_PUNCT && (*p == '(' || *p == '{'))
                depth++;
            else if (f->tok[j].kind == T_PUNCT && *p == ')')
                depth--;
            else if (f->tok[j].kind == T_PUNCT && *p == '}') {
                if (depth-- == 0)
                    break;
            } else if (depth == 0 && f->tok[j].kind == T_PUNCT && *p == ',')
                expect = 1;
            else if (depth == 0 && expect && f->tok[j].kind == T_IDENT) {
                add_name(f, &nm->locals, j);
                expect = 0;
            }
        }
    }
    return skip_balanced(f, i);
}

/* Is token i (an identifier) a declarator's name: followed by what ends
** or continues a declarator? */
static int declarator_name(const source *f, size_t i)
{
    size_t j = code(f, i + 1);

    if (f->tok[i].kind != T_IDENT || is_keyword(f, i) || j >= f->ntok)
        return 0;
    return tok_is(f, j, "(") || tok_is(f, j, "[") || tok_is(f, j, "=") ||
           tok_is(f, j, ";") || tok_is(f, j, ",") || tok_is(f, j, ")");
}

/*
** One file-scope declaration from token i: its names go into nm (locals
** when static or typedef; externs for a function defined without
** static); a ray__ name's declaration is noted.  Returns the token
** after it.
*/
static size_t declaration(const source *f, size_t i, names *nm,
                          const name_set *function_macros)
{
    size_t start = i, first = f->ntok;
    int is_static = 0, is_typedef = 0, expect = 1, depth = 0, defined = 0;

    /* A function-like macro at file scope (an X-macro's expansion) is a
    ** declaration of its own. */
    if (f->tok[i].kind == T_IDENT &&
        set_has(function_macros, f->text + f->tok[i].at, f->tok[i].len) &&
        tok_is(f, code(f, i + 1), "(")) {
        i = skip_balanced(f, code(f, i + 1));
        return tok_is(f, i, ";") ? code(f, i + 1) : i;
    }
    while (i < f->ntok) {
        const char *p = f->text + f->tok[i].at;

        if (tok_is(f, i, "static"))
            is_static = 1;
        else if (tok_is(f, i, "typedef"))
            is_typedef = 1;
        if (tok_is(f, i, "struct") || tok_is(f, i, "union") ||
            tok_is(f, i, "enum")) {
            i = specifier(f, i, nm);
            continue;
        }
        if (tok_is(f, i, "__attribute__") || tok_is(f, i, "__declspec")) {
            i = code(f, i + 1);
            if (tok_is(f, i, "("))
                i = skip_balanced(f, i);
            continue;
        }
        if (expect && declarator_name(f, i)) {
            expect = 0;
            if (first == f->ntok)
                first = i;
            if (is_static || is_typedef)
                add_name(f, &nm->locals, i);
        } else if (f->tok[i].kind == T_PUNCT) {
            if (*p == '(' || *p == '[')
                depth++;
            else if (*p == ')' || *p == ']')
                depth--;
            else if (*p == '=' && depth == 0) {
                /* The initializer, to the next ',' or ';'. */
                i = code(f, i + 1);
                while (i < f->ntok && !tok_is(f, i, ",") &&
                       !tok_is(f, i, ";"))
                    i = tok_is(f, i, "{") || tok_is(f, i, "(") ||
                                tok_is(f, i, "[")
                            ? skip_balanced(f, i)
                            : code(f, i + 1);
                continue;
            } else if (*p == ',' && depth == 0)
                expect = 1;
            else if (*p == ';' && depth == 0) {
                i = code(f, i + 1);
                break;
            } else if (*p == '{' && depth == 0) {
                defined = 1;        /* a function's body */
                i = skip_balanced(f, i);
                break;
            }
        }
        i = code(f, i + 1);
    }
    if (first < f->ntok) {
        const char *name = f->text + f->tok[first].at;
        if (defined && !is_static)
            add_name(f, &nm->externs, first);
        if (!is_static && !is_typedef && strncmp(name, "ray__", 5) == 0)
            note_decl(nm, f, start, first);
    }
    return i;
}

/* The macros a file defines (and which of them take arguments). */
static void find_macros(const source *f, names *nm)
{
    size_t i;

    for (i = 0; i < f->ntok; i++) {
        size_t d, m;
        if (!f->tok[i].pp_start)
            continue;
        d = directive_name(f, i);
        if (d >= f->ntok || !tok_is(f, d, "define"))
            continue;
        m = d + 1;
        if (m >= f->ntok || !f->tok[m].pp || f->tok[m].kind != T_IDENT)
            die("%s: a #define without a name", f->path);
        add_name(f, &nm->macros, m);
        if (m + 1 < f->ntok && tok_is(f, m + 1, "(") &&
            f->tok[m + 1].at == f->tok[m].at + f->tok[m].len)
            add_name(f, &nm->function_macros, m);
    }
}

static void find_names(const source *f, names *nm,
                       const name_set *function_macros)
{
    size_t i = code(f, 0);

    while (i < f->ntok) {
        if (tok_is(f, i, ";")) {            /* an empty declaration */
            i = code(f, i + 1);
            continue;
        }
        i = declaration(f, i, nm, function_macros);
    }
}

/* ------------------------------------------------------------- sources */

typedef struct program {
    const char *srcdir;
    source *files;              /* every file read, headers too */
    names *nm;
    size_t nfiles, cap;
    name_set spelled_in;        /* "file\001ident": ident in file */
    name_set header_names;      /* every identifier any header spells */
    name_set header_macros;
    name_set function_macros;
    name_set staticize;         /* ray__ functions defined in a file */
    int *scanned;               /* includes followed (load_includes) */
    int *emitted;               /* headers written out */
    int *emitted_under_if;      /* ... first inside a file's #if */
    FILE *out;
} program;

/* The file at path (read and tokenized on first use), or -1 when it does
** not exist. */
static int load(program *pg, const char *path, int header)
{
    size_t i;
    source f;

    for (i = 0; i < pg->nfiles; i++)
        if (strcmp(pg->files[i].path, path) == 0)
            return (int)i;
    f.text = read_file(path);
    if (f.text == NULL)
        return -1;
    f.path = xstrndup(path, strlen(path));
    f.header = header;
    tokenize(&f);
    if (pg->nfiles == pg->cap) {
        pg->cap = pg->cap * 2 + 64;
        pg->files = xrealloc(pg->files, pg->cap * sizeof *pg->files);
        pg->nm = xrealloc(pg->nm, pg->cap * sizeof *pg->nm);
        pg->scanned = xrealloc(pg->scanned, pg->cap * sizeof *pg->scanned);
        pg->emitted = xrealloc(pg->emitted, pg->cap * sizeof *pg->emitted);
        pg->emitted_under_if =
            xrealloc(pg->emitted_under_if, pg->cap * sizeof(int));
    }
    pg->files[pg->nfiles] = f;
    memset(&pg->nm[pg->nfiles], 0, sizeof pg->nm[pg->nfiles]);
    pg->scanned[pg->nfiles] = 0;
    pg->emitted[pg->nfiles] = 0;
    pg->emitted_under_if[pg->nfiles] = 0;
    return (int)pg->nfiles++;
}

/* The private header a quoted #include at token i names (loaded), or -1
** for any other include (a system header, ray.h) or directive. */
static int private_include(program *pg, int fi, size_t i)
{
    const source *f = &pg->files[fi];
    size_t d = directive_name(f, i), q = d + 1;
    char *path;
    int h;

    if (d >= f->ntok || !tok_is(f, d, "include") || q >= f->ntok ||
        !f->tok[q].pp || f->text[f->tok[q].at] != '"')
        return -1;
    path = xmalloc(strlen(pg->srcdir) + f->tok[q].len + 2);
    sprintf(path, "%s/%.*s", pg->srcdir, (int)f->tok[q].len - 2,
            f->text + f->tok[q].at + 1);
    h = load(pg, path, 1);
    free(path);
    return h;
}

/* Load every private header reachable from file fi. */
static void load_includes(program *pg, int fi)
{
    size_t i;

    pg->scanned[fi] = 1;
    for (i = 0; i < pg->files[fi].ntok; i++)
        if (pg->files[fi].tok[i].pp_start) {
            int h = private_include(pg, fi, i);
            if (h >= 0 && !pg->scanned[h])
                load_includes(pg, h);
        }
}

static void spell(program *pg, int fi)
{
    const source *f = &pg->files[fi];
    size_t i, n = strlen(f->path);
    char *key = NULL;
    size_t cap = 0;

    for (i = 0; i < f->ntok; i++) {
        if (f->tok[i].kind != T_IDENT)
            continue;
        if (f->header)
            set_add(&pg->header_names, f->text + f->tok[i].at,
                    f->tok[i].len);
        if (n + f->tok[i].len + 2 > cap) {
            cap = n + f->tok[i].len + 64;
            key = xrealloc(key, cap);
        }
        sprintf(key, "%s\001%.*s", f->path, (int)f->tok[i].len,
                f->text + f->tok[i].at);
        set_add(&pg->spelled_in, key, strlen(key));
    }
    free(key);
}

/* Is name spelled in a file other than fi (a header, or another source
** of nsrc)? */
static int spelled_elsewhere(const program *pg, int fi, const char *name,
                             int nsrc)
{
    int g, found = 0;

    if (set_has(&pg->header_names, name, strlen(name)))
        return 1;
    for (g = 0; g < nsrc && !found; g++) {
        char *key;
        if (g == fi)
            continue;
        key = xmalloc(strlen(pg->files[g].path) + strlen(name) + 2);
        sprintf(key, "%s\001%s", pg->files[g].path, name);
        found = set_has(&pg->spelled_in, key, strlen(key));
        free(key);
    }
    return found;
}

/* ------------------------------------------------------------- output */

static void emit_file(program *pg, int fi, const name_set *rename,
                      const char *prefix, int depth_if);

/* Header h, at its first inclusion: written out whole (its own private
** includes inlined in their turn). */
static void emit_header(program *pg, int h, int under_if, const char *by)
{
    if (pg->emitted[h]) {
        if (pg->emitted_under_if[h] && !under_if)
            die("%s: included under an #if first, then unconditionally by "
                "%s: include it unconditionally in the first file",
                pg->files[h].path, by);
        fprintf(pg->out, "/* %s: inlined above */\n",
                pg->files[h].path + strlen(pg->srcdir) + 1);
        return;
    }
    pg->emitted[h] = 1;
    pg->emitted_under_if[h] = under_if;
    fprintf(pg->out, "/* ---- %s ---- */\n",
            pg->files[h].path + strlen(pg->srcdir) + 1);
    emit_file(pg, h, NULL, NULL, under_if);
    fprintf(pg->out, "/* ---- end of %s ---- */\n",
            pg->files[h].path + strlen(pg->srcdir) + 1);
}

/* Is declaration start token i of file fi one to make RAY__STATIC? */
static int staticized(const program *pg, int fi, size_t i)
{
    const names *nm = &pg->nm[fi];
    size_t k;

    for (k = 0; k < nm->ndecl; k++)
        if (nm->decl_start[k] == i)
            return set_has(&pg->staticize, nm->decl_name[k],
                           strlen(nm->decl_name[k]));
    return 0;
}

static int renamed(const source *f, size_t i, const name_set *rename)
{
    size_t p;

    if (rename == NULL || f->tok[i].kind != T_IDENT ||
        !set_has(rename, f->text + f->tok[i].at, f->tok[i].len))
        return 0;
    if (i == 0)
        return 1;
    p = i - 1;          /* a member's name stays, and a directive's */
    return !(tok_is(f, p, ".") || tok_is(f, p, "->") || f->tok[p].pp_start);
}

/*
** File fi's text with its private includes inlined, its names in rename
** given prefix, and its ray__ declarations made RAY__STATIC.  depth_if:
** the #if nesting the file is written under (a source wrapped by -if).
*/
static void emit_file(program *pg, int fi, const name_set *rename,
                      const char *prefix, int depth_if)
{
    const source *f = &pg->files[fi];
    size_t i, from = 0;
    int depth = depth_if;

    for (i = 0; i < f->ntok; i++) {
        const token *t = &f->tok[i];
        if (t->pp_start) {
            size_t d = directive_name(f, i);
            int h;
            if (!f->header && d < f->ntok &&
                (tok_is(f, d, "if") || tok_is(f, d, "ifdef") ||
                 tok_is(f, d, "ifndef")))
                depth++;
            else if (!f->header && tok_is(f, d, "endif"))
                depth--;
            h = private_include(pg, fi, i);
            if (h >= 0) {
                size_t end = directive_end(f, i);
                fwrite(f->text + from, 1, t->at - from, pg->out);
                emit_header(pg, h, depth > 0, f->path);
                /* Resume after the directive's line. */
                from = f->tok[end - 1].at + f->tok[end - 1].len;
                while (f->text[from] != '\0' && f->text[from] != '\n')
                    from++;
                if (f->text[from] == '\n')
                    from++;
                i = end - 1;
                continue;
            }
        }
        if (!t->pp && staticized(pg, fi, i)) {
            fwrite(f->text + from, 1, t->at - from, pg->out);
            fputs("RAY__STATIC ", pg->out);
            from = t->at;
        }
        if (renamed(f, i, rename)) {
            fwrite(f->text + from, 1, t->at - from, pg->out);
            fprintf(pg->out, "%s%.*s", prefix, (int)t->len,
                    f->text + t->at);
            from = t->at + t->len;
        }
    }
    fputs(f->text + from, pg->out);
    if (from < strlen(f->text) && f->text[strlen(f->text) - 1] != '\n')
        fputc('\n', pg->out);
}

/* The prefix of a source's renamed names: its path below SRCDIR, letters
** and digits kept, then "__" (src/accel/sah.c: "accel_sah__"). */
static char *prefix_of(const program *pg, const char *path)
{
    size_t n = strlen(pg->srcdir), i, o = 0;
    char *p;

    if (strncmp(path, pg->srcdir, n) == 0 && path[n] == '/')
        path += n + 1;
    p = xmalloc(strlen(path) + 3);
    for (i = 0; path[i] != '\0' && strcmp(path + i, ".c") != 0; i++)
        p[o++] = ident_char((unsigned char)path[i]) ? path[i] : '_';
    strcpy(p + o, "__");
    return p;
}

/* A source's own header files first, outside its #if (-if). */
static void emit_includes_of(program *pg, int fi)
{
    size_t i;

    for (i = 0; i < pg->files[fi].ntok; i++)
        if (pg->files[fi].tok[i].pp_start) {
            int h = private_include(pg, fi, i);
            if (h >= 0 && !pg->emitted[h])
                emit_header(pg, h, 0, pg->files[fi].path);
        }
}

static void set_merge(name_set *to, const name_set *from)
{
    size_t i;

    for (i = 0; i < from->cap; i++)
        if (from->slot[i] != NULL)
            set_add(to, from->slot[i], strlen(from->slot[i]));
}

/* Every file's names, the identifiers each spells, and which ray__
** functions become RAY__STATIC: those a header declares by name (not
** through a macro, which this cannot make static) and a source defines
** without static. */
static void analyse(program *pg, int nsrc)
{
    name_set declared;
    int fi;
    size_t i;

    memset(&declared, 0, sizeof declared);
    for (fi = 0; fi < (int)pg->nfiles; fi++) {
        find_macros(&pg->files[fi], &pg->nm[fi]);
        set_merge(&pg->function_macros, &pg->nm[fi].function_macros);
        if (pg->files[fi].header)
            set_merge(&pg->header_macros, &pg->nm[fi].macros);
    }
    for (fi = 0; fi < (int)pg->nfiles; fi++) {
        find_names(&pg->files[fi], &pg->nm[fi], &pg->function_macros);
        spell(pg, fi);
    }
    for (fi = nsrc; fi < (int)pg->nfiles; fi++)
        for (i = 0; i < pg->nm[fi].ndecl; i++)
            set_add(&declared, pg->nm[fi].decl_name[i],
                    strlen(pg->nm[fi].decl_name[i]));
    for (fi = 0; fi < nsrc; fi++) {
        const name_set *ext = &pg->nm[fi].externs;
        for (i = 0; i < ext->cap; i++)
            if (ext->slot[i] != NULL &&
                strncmp(ext->slot[i], "ray__", 5) == 0 &&
                set_has(&declared, ext->slot[i], strlen(ext->slot[i])))
                set_add(&pg->staticize, ext->slot[i], strlen(ext->slot[i]));
    }
}

/* The names source fi renames: its own that another file spells (but
** the library's namespace), and its macros that a header defines too. */
static void names_to_rename(const program *pg, int fi, int nsrc,
                            name_set *rename)
{
    const names *nm = &pg->nm[fi];
    size_t i;

    for (i = 0; i < nm->locals.cap; i++) {
        const char *n = nm->locals.slot[i];
        if (n == NULL || strncmp(n, "ray_", 4) == 0 ||
            strncmp(n, "RAY_", 4) == 0)
            continue;
        if (spelled_elsewhere(pg, fi, n, nsrc))
            set_add(rename, n, strlen(n));
    }
    for (i = 0; i < nm->macros.cap; i++) {
        const char *m = nm->macros.slot[i];
        if (m != NULL && set_has(&pg->header_macros, m, strlen(m)))
            set_add(rename, m, strlen(m));
    }
}

/* Source fi, under #if wrap when wrap is not NULL, then the #undef of
** each macro it defined. */
static void emit_source(program *pg, int fi, int nsrc, const char *wrap)
{
    const names *nm = &pg->nm[fi];
    char *prefix = prefix_of(pg, pg->files[fi].path);
    name_set rename;
    size_t i;

    memset(&rename, 0, sizeof rename);
    names_to_rename(pg, fi, nsrc, &rename);
    fprintf(pg->out, "\n/* ======== %s ======== */\n", pg->files[fi].path);
    if (wrap != NULL) {
        emit_includes_of(pg, fi);
        fprintf(pg->out, "#if %s\n", wrap);
    }
    emit_file(pg, fi, &rename, prefix, wrap != NULL);
    for (i = 0; i < nm->macros.cap; i++) {
        const char *m = nm->macros.slot[i];
        if (m != NULL)
            fprintf(pg->out, "#undef %s%s\n",
                    set_has(&rename, m, strlen(m)) ? prefix : "", m);
    }
    if (wrap != NULL)
        fprintf(pg->out, "#endif /* %s */\n", wrap);
    free(prefix);
}

static void usage(void)
{
    die("usage: amalgamate -o OUT -I SRCDIR [-p PROLOGUE] "
        "[-if FILE COND]... FILE.c...");
}

int main(int argc, char **argv)
{
    program pg;
    const char *out = NULL, *prologue = NULL;
    const char **cond_file = xmalloc((size_t)argc * sizeof(char *));
    const char **cond = xmalloc((size_t)argc * sizeof(char *));
    int ncond = 0, nsrc = 0, a, fi, k;

    memset(&pg, 0, sizeof pg);
    pg.srcdir = "src";
    for (a = 1; a < argc && argv[a][0] == '-'; a++) {
        if (strcmp(argv[a], "-o") == 0 && a + 1 < argc)
            out = argv[++a];
        else if (strcmp(argv[a], "-I") == 0 && a + 1 < argc)
            pg.srcdir = argv[++a];
        else if (strcmp(argv[a], "-p") == 0 && a + 1 < argc)
            prologue = argv[++a];
        else if (strcmp(argv[a], "-if") == 0 && a + 2 < argc) {
            cond_file[ncond] = argv[++a];
            cond[ncond++] = argv[++a];
        } else
            usage();
    }
    if (out == NULL || a == argc)
        usage();

    /* The sources first (indices 0 .. nsrc-1), then their headers. */
    for (; a < argc; a++, nsrc++)
        if (load(&pg, argv[a], 0) != nsrc)
            die("cannot read %s (or given twice)", argv[a]);
    for (fi = 0; fi < nsrc; fi++)
        load_includes(&pg, fi);
    analyse(&pg, nsrc);

    pg.out = fopen(out, "w");
    if (pg.out == NULL)
        die("cannot write %s", out);
    if (prologue != NULL) {
        char *text = read_file(prologue);
        if (text == NULL)
            die("cannot read %s", prologue);
        fputs(text, pg.out);
        free(text);
    }
    for (fi = 0; fi < nsrc; fi++) {
        const char *wrap = NULL;
        for (k = 0; k < ncond; k++)
            if (strcmp(cond_file[k], pg.files[fi].path) == 0)
                wrap = cond[k];
        emit_source(&pg, fi, nsrc, wrap);
    }
    if (fclose(pg.out) != 0)
        die("cannot write %s", out);
    return 0;
}
