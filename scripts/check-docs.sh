#!/bin/sh
# SPDX-License-Identifier: MIT
# check-docs.sh -- the man pages say what include/ray.h says (issue 18).
#
# ray.h and the ray_*(3) pages both state every prototype, by hand; this
# check keeps them from drifting apart.  include/ray.h is the reference.
# It fails, naming the function, the header line and the page, when
#
#   * a RAY_API function of ray.h is in no page's SYNOPSIS, or in two;
#   * a SYNOPSIS prototype differs from ray.h: its return type (.Ft), or
#     the number, types or names of its parameters (.Fn, or .Fo/.Fa/.Fc),
#     compared after white space is normalised ("T*p" reads as "T *p");
#   * a SYNOPSIS shows a function that ray.h does not declare (a stale
#     page), or a page's NAME section (.Nm) lists one;
#   * a function of a page's SYNOPSIS is missing from that page's NAME
#     section, or a page is not named after a function of its SYNOPSIS,
#     or its .Dt title is not its file name in capitals;
#   * a function has neither a page of its own nor an install link to the
#     page that documents it: the links are the Makefile's MLINKS, derived
#     from each page's NAME section and passed in by "make docs-test" as
#     the environment variable MLINKS (page:alias ...), so that the list
#     the install rule uses is the one checked;
#   * a man page cross-references (.Xr name 3) a ray_ page or link that
#     is not installed;
#   * a public type of ray.h (a typedef named ray_*) is mentioned in no
#     man page.
#
# Usage: scripts/check-docs.sh [HEADER [MANDIR]]
# (defaults include/ray.h and man, relative to the top directory).
# The parsing is POSIX sh and awk (mawk, gawk, BSD awk): no Python needed.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
header=${1:-$top/include/ray.h}
mandir=${2:-$top/man}
# Show paths relative to the top directory, as a user would type them.
rel() { case "$1" in "$top"/*) echo "${1#"$top"/}" ;; *) echo "$1" ;; esac; }

pages3=$(ls "$mandir"/man3/*.3 2>/dev/null || true)
pages7=$(ls "$mandir"/man7/*.7 2>/dev/null || true)
if [ -z "$pages3" ]; then
    echo "docs-test: no man pages in $(rel "$mandir")/man3" >&2
    exit 1
fi
if [ -z "${MLINKS+set}" ]; then
    links_given=0
    echo "docs-test: MLINKS not set (run it as 'make docs-test' to check the install links too)"
else
    links_given=1
fi

# shellcheck disable=SC2086  # the page lists are split on purpose
awk -v header="$header" -v top="$top/" -v mlinks="${MLINKS:-}" \
    -v links_given="$links_given" '
function rel(path) { return index(path, top) == 1 ? substr(path, length(top) + 1) : path }
function trim(s) { sub(/^[ \t]+/, "", s); sub(/[ \t]+$/, "", s); return s }

# One spelling of a C type or parameter: single spaces, "T *p" and
# "T **p" (a space before the stars, none after), "a[3]".
function norm(s) {
    gsub(/[ \t\r\n]+/, " ", s)
    gsub(/ *\* */, "*", s)
    gsub(/\*/, " *", s)
    while (sub(/\* \*/, "**", s)) ;
    gsub(/ *\[ */, "[", s); gsub(/ *\] */, "]", s)
    gsub(/ *\( */, "(", s); gsub(/ *\) */, ")", s); gsub(/ *, */, ", ", s)
    return trim(s)
}

# Split a parameter list at the commas outside parentheses; "void" and
# "" are no parameters.  Returns the count, fills out[1..n].
function split_params(s, out,    n, depth, i, c, cur) {
    n = 0; depth = 0; cur = ""
    for (i = 1; i <= length(s); i++) {
        c = substr(s, i, 1)
        if (c == "(") depth++
        else if (c == ")") depth--
        if (c == "," && depth == 0) { out[++n] = norm(cur); cur = "" }
        else cur = cur c
    }
    cur = norm(cur)
    if (n > 0 || (cur != "" && cur != "void")) out[++n] = cur
    return n
}

function problem(msg) { problems++; print "docs-test: " msg }

# ------------------------------------------------------------ ray.h
# Record a RAY_API declaration "RET NAME(PARAMS)".
function header_decl(decl, line,    open, shut, head, name, n, i, p) {
    decl = norm(decl)
    open = index(decl, "(")
    shut = length(decl)
    while (shut > 0 && substr(decl, shut, 1) != ")") shut--
    head = substr(decl, 1, open - 1)
    if (open == 0 || shut < open || !match(head, /[A-Za-z_][A-Za-z0-9_]*$/)) {
        problem(rel(header) ":" line ": cannot read this RAY_API declaration as RET NAME(PARAMS): " decl)
        return
    }
    name = substr(head, RSTART)
    if (name in h_line) {
        problem(rel(header) ":" line ": " name " is declared twice (also line " h_line[name] ")")
        return
    }
    h_names[++h_count] = name
    h_line[name] = line
    h_ret[name] = norm(substr(head, 1, RSTART - 1))
    n = split_params(substr(decl, open + 1, shut - open - 1), p)
    h_nparams[name] = n
    for (i = 1; i <= n; i++) h_param[name, i] = p[i]
}

# Remove comments, keeping their state across lines.
function uncomment(s,    out, i) {
    out = ""
    while (s != "") {
        if (in_comment) {
            i = index(s, "*/")
            if (i == 0) return out
            s = substr(s, i + 2); in_comment = 0
        } else {
            i = index(s, "/*")
            if (i == 0) {
                if ((i = index(s, "//")) > 0) s = substr(s, 1, i - 1)
                return out s
            }
            out = out substr(s, 1, i - 1) " "
            s = substr(s, i + 2); in_comment = 1
        }
    }
    return out
}

# One spelling of a C declaration for comparison: no comments (removed
# before), single spaces, none around punctuation.
function cnorm(s) {
    gsub(/[ \t\r\n]+/, " ", s)
    gsub(/ ?\* ?/, "*", s); gsub(/ ?; ?/, ";", s); gsub(/ ?, ?/, ",", s)
    gsub(/ ?[{] ?/, "{", s); gsub(/ ?[}] ?/, "}", s)
    gsub(/ ?\( ?/, "(", s); gsub(/ ?\) ?/, ")", s)
    gsub(/ ?\[ ?/, "[", s); gsub(/ ?\] ?/, "]", s); gsub(/ ?= ?/, "=", s)
    return trim(s)
}

# Collect a typedef or enum statement from comment-free C lines, up to
# its ";" outside braces; returns 1 when one is complete in st_text.
function stmt_feed(s, line,    o, c) {
    if (!st_on) {
        if (s !~ /^[ \t]*(typedef|enum)([ \t{]|$)/) return 0
        st_on = 1; st_text = ""; st_depth = 0; st_line = line
    }
    st_text = st_text " " s
    o = gsub(/[{]/, "{", s); c = gsub(/[}]/, "}", s)
    st_depth += o - c
    if (st_depth <= 0 && index(s, ";")) { st_on = 0; st_text = cnorm(st_text); return 1 }
    return 0
}

# What a statement defines: ray_X for "typedef ... (*ray_X)(...);" and
# "typedef ... ray_X;", "enum RAY_FIRST" for an enum of RAY_ constants.
function stmt_key(t) {
    if (match(t, /\(\*ray_[A-Za-z0-9_]*\)/)) return substr(t, RSTART + 2, RLENGTH - 3)
    if (match(t, /ray_[A-Za-z0-9_]*;$/)) return substr(t, RSTART, RLENGTH - 1)
    if (t ~ /^enum[{]/ && match(t, /RAY_[A-Za-z0-9_]*/)) return "enum " substr(t, RSTART, RLENGTH)
    return ""
}

FILENAME == header {
    s = uncomment($0)
    if (in_directive || s ~ /^[ \t]*#/) {      # the preprocessor: not C
        if (match(s, /^[ \t]*#[ \t]*define[ \t]+RAY_[A-Za-z0-9_]*/)) {
            n = substr(s, RSTART, RLENGTH); sub(/^.*[ \t]/, "", n)
            v = substr(s, RSTART + RLENGTH); gsub(/[ \t]+/, " ", v); def_value[n] = trim(v)
            if (n != "RAY_H" && n != "RAY_API" && !(n in const_line)) { const_line[n] = FNR; consts[++const_count] = n }
        }
        in_directive = ($0 ~ /\\$/)
        next
    }
    # The body of a static inline helper: skipped to its closing brace.
    if (in_body) {
        if (substr(s, 1, 1) == "}") in_body = 0
        next
    }
    if (!collecting && s ~ /(^|[^A-Za-z0-9_])RAY_API[ \t]/) {
        collecting = 1; decl = ""; decl_line = FNR; decl_end = ";"
        sub(/^.*RAY_API[ \t]+/, "", s)
    }
    # A static inline ray_* helper is API too (no symbol, but documented):
    # the head of its definition, up to the brace, is its prototype.
    if (!collecting && s ~ /^static inline [^(]*ray_[A-Za-z0-9_]*\(/) {
        collecting = 1; decl = ""; decl_line = FNR; decl_end = "{"
        # (the return type keeps "static inline", as the page shows it)
    }
    if (collecting) {
        decl = decl " " s
        if (index(decl, decl_end)) {
            header_decl(substr(decl, 1, index(decl, decl_end) - 1), decl_line)
            collecting = 0
            if (decl_end == "{") in_body = (s !~ /[}][ \t]*$/)
        }
        next
    }
    if (stmt_feed(s, FNR) && (k = stmt_key(st_text)) != "") {
        h_stmt[k] = st_text; h_stmt_line[k] = st_line
        if (k !~ /^enum /) { type_line[k] = st_line; types[++type_count] = k }
        else {                                  # its constants, for later
            t = st_text
            while (match(t, /[{,]RAY_[A-Za-z0-9_]*/)) {
                n = substr(t, RSTART + 1, RLENGTH - 1); t = substr(t, RSTART + RLENGTH)
                if (!(n in const_line)) { const_line[n] = st_line; consts[++const_count] = n }
            }
        }
    }
    next
}

# ------------------------------------------------------------ man pages
# The arguments of an mdoc macro line: words, or "quoted strings" in
# which "" is a quote; \& and \e are the mdoc escapes a prototype may need.
function mdoc_args(line, out,    n, s, w) {
    n = 0; s = line
    sub(/^\.[A-Za-z]+[ \t]*/, "", s)
    while ((s = trim(s)) != "") {
        if (substr(s, 1, 1) == "\"") {
            s = substr(s, 2); w = ""
            while (s != "") {
                if (substr(s, 1, 2) == "\"\"") { w = w "\""; s = substr(s, 3) }
                else if (substr(s, 1, 1) == "\"") { s = substr(s, 2); break }
                else { w = w substr(s, 1, 1); s = substr(s, 2) }
            }
        } else {
            match(s, /^[^ \t]+/); w = substr(s, 1, RLENGTH); s = substr(s, RLENGTH + 1)
        }
        gsub(/\\&/, "", w); gsub(/\\e/, "\\", w)
        out[++n] = w
    }
    return n
}

function page_of(path,    p) { p = path; sub(/^.*\//, "", p); sub(/\.[0-9]$/, "", p); return p }

# Record the SYNOPSIS prototype collected in fo_* on the current page.
function man_proto(line,    key) {
    if (fo_ret == "")
        problem(rel(FILENAME) ":" line ": " fo_name " has no return type (.Ft) before it in the SYNOPSIS")
    if (fo_name in m_page) {
        problem(fo_name " is in the SYNOPSIS of two pages, " rel(m_file[fo_name]) " and " rel(FILENAME) ": keep it on one (the other can link to it with .Xr)")
        return
    }
    m_page[fo_name] = page; m_file[fo_name] = FILENAME; m_line[fo_name] = line
    m_ret[fo_name] = fo_ret; m_nparams[fo_name] = fo_n
    syn[page, fo_name] = 1
    m_names[++m_count] = fo_name
    fo_ret = ""
}

function shown_type(k, t, line,    where, n, i, hp, mp) {
    where = rel(FILENAME) ":" line
    if (!(k in h_stmt)) {
        problem(where ": shows " (k ~ /^enum / ? "an enum starting with " substr(k, 6) : "a type " k) ", which " rel(header) " does not define: remove it or correct it")
        return
    }
    shown[k] = 1
    if (t == h_stmt[k]) return
    # Name the first member (or statement piece) that differs.
    n = split(h_stmt[k], hp, /;/); split(t, mp, /;/)
    for (i = 1; i <= n && hp[i] == mp[i]; i++) ;
    problem(where ": its copy of " (k ~ /^enum / ? "the enum of " substr(k, 6) : k) " differs from " rel(header) ":" h_stmt_line[k] " (comments and layout aside):\n    ray.h: " hp[i] "\n    page:  " mp[i])
}

FNR == 1 {
    page = page_of(FILENAME); section = ""; in_display = 0; in_literal = 0
    fo_name = ""; fo_ret = ""
    if (FILENAME ~ /\.3$/) pages[++page_count] = FILENAME
}

# Cross-references to our own pages, anywhere in any page.
/^\.Xr ray_[A-Za-z0-9_]* 3/ { xref[++xref_count] = $2; xref_where[xref_count] = rel(FILENAME) ":" FNR }
/^\.Dt / { dt[FILENAME] = $2 " " $3 }
FNR <= 3 && tolower($0) ~ /derived from include\/ray\.h/ {
    problem(rel(FILENAME) ":" FNR ": says it is derived from include/ray.h; it is not (it is written by hand and checked by scripts/check-docs.sh): write \"written by hand from include/ray.h\"")
}
/^\.Sh / { section = $2; next }

# Every mention of a name, for the public types and constants.
{ line = $0; while (match(line, /(ray|RAY)_[A-Za-z0-9_]*/)) { mentioned[substr(line, RSTART, RLENGTH)] = 1; line = substr(line, RSTART + RLENGTH) } }

# A copy of a ray.h type in a literal display (any section of any page)
# must declare what ray.h declares; its comments may be shorter.
/^\.Bd[ \t]+-literal/ { in_literal = 1; in_comment = 0; st_on = 0 }
/^\.Ed/ { in_literal = 0 }
in_literal && !/^\./ {
    s = $0
    gsub(/\\&/, "", s); gsub(/\\\(dq/, "\"", s); gsub(/\\\(aq/, "'\''", s)
    gsub(/\\-/, "-", s); gsub(/\\e/, "\\", s)
    if (stmt_feed(uncomment(s), FNR) && (k = stmt_key(st_text)) != "")
        shown_type(k, st_text, st_line)
}

FILENAME !~ /\.3$/ { next }

section == "NAME" && /^\.Nm / {
    n = mdoc_args($0, a)
    if (n >= 1) { nm[page, a[1]] = 1; nm_list[++nm_count] = a[1]; nm_page[nm_count] = FILENAME; nm_line[nm_count] = FNR }
    next
}

section != "SYNOPSIS" { next }
/^\.Bd/ { in_display = 1; next }
/^\.Ed/ { in_display = 0; next }
in_display { next }
/^\.Fd[ \t]+#define[ \t]/ {             # a constant: ray.h defines it, as shown
    n = split($0, a, /[ \t]+/); v = ""
    for (i = 4; i <= n; i++) v = v (i > 4 ? " " : "") a[i]
    if (!(a[3] in def_value))
        problem(rel(FILENAME) ":" FNR ": the SYNOPSIS shows #define " a[3] ", which " rel(header) " does not define")
    else if (v != "" && v != def_value[a[3]])
        problem(rel(FILENAME) ":" FNR ": the SYNOPSIS shows #define " a[3] " " v ", but " rel(header) ":" const_line[a[3]] " defines it as " def_value[a[3]])
    next
}
/^\.Ft / { fo_ret = ""; n = mdoc_args($0, a); for (i = 1; i <= n; i++) fo_ret = fo_ret " " a[i]; fo_ret = norm(fo_ret); next }
/^\.Fn / {
    n = mdoc_args($0, a)
    fo_name = a[1]; fo_n = 0
    for (i = 2; i <= n; i++) {
        if (n == 2 && a[i] == "void") break
        m_param[a[1], ++fo_n] = norm(a[i])
    }
    man_proto(FNR); fo_name = ""
    next
}
/^\.Fo / { n = mdoc_args($0, a); fo_name = a[1]; fo_n = 0; fo_start = FNR; next }
/^\.Fa / && fo_name != "" {
    n = mdoc_args($0, a)
    for (i = 1; i <= n; i++) m_param[fo_name, ++fo_n] = norm(a[i])
    next
}
/^\.Fc/ && fo_name != "" { man_proto(fo_start); fo_name = ""; next }

# ------------------------------------------------------------ compare
function signature(ret, name, n, arr, key,    s, i) {
    s = ret (ret ~ /\*$/ ? "" : " ") name "("
    for (i = 1; i <= n; i++) s = s (i > 1 ? ", " : "") arr[key, i]
    return s (n == 0 ? "void)" : ")")
}

END {
    for (k in shown) shown_count++
    if (h_count == 0) problem(rel(header) ": no RAY_API declarations found")
    n_links = split(mlinks, words, /[ \t\n]+/)
    for (i = 1; i <= n_links; i++) {
        if (words[i] == "") continue
        split(words[i], pa, ":")
        link_page[pa[2]] = pa[1]; links[++link_count] = pa[2]
    }

    for (k = 1; k <= h_count; k++) {
        f = h_names[k]; where = rel(header) ":" h_line[f]
        hsig = signature(h_ret[f], f, h_nparams[f], h_param, f)
        if (!(f in m_page)) {
            problem(where ": " f " is in no man page SYNOPSIS: add \".Ft " h_ret[f] "\" and \".Fo " f "\" ... to the SYNOPSIS, and \".Nm " f "\" to the NAME section, of the page in man/man3 that documents its family (or write man/man3/" f ".3)")
            continue
        }
        file = rel(m_file[f]); mwhere = file ":" m_line[f]
        msig = signature(m_ret[f], f, m_nparams[f], m_param, f)
        if (h_ret[f] != m_ret[f])
            problem(f ": return type differs: " where " says \"" h_ret[f] "\", " mwhere " (.Ft) says \"" m_ret[f] "\"")
        if (h_nparams[f] != m_nparams[f]) {
            problem(f ": " h_nparams[f] " parameters in " where ", " m_nparams[f] " in the SYNOPSIS of " mwhere ":\n    ray.h: " hsig "\n    page:  " msig)
        } else {
            for (i = 1; i <= h_nparams[f]; i++)
                if (h_param[f, i] != m_param[f, i])
                    problem(f ": parameter " i " differs: " where " has \"" h_param[f, i] "\", " mwhere " has \"" m_param[f, i] "\" (type and name must match ray.h)")
        }
        if (!((m_page[f], f) in nm))
            problem(file ": " f " is in the SYNOPSIS but not in the NAME section: add \".Nm " f " ,\" there (apropos, whatis and the install link " f ".3 come from NAME)")
        lp = (f in link_page) ? link_page[f] : ""
        if (links_given && m_page[f] != f && lp != m_page[f])
            problem(f ": documented on " file " but " (lp == "" ? "the Makefile MLINKS has no install link " f ".3 to it" : "the Makefile MLINKS links " f ".3 to " lp ".3") "; MLINKS should be derived from the NAME section of each page (each .Nm but the page name itself)")
    }

    for (k = 1; k <= m_count; k++) {
        f = m_names[k]
        if (!(f in h_line))
            problem(rel(m_file[f]) ":" m_line[f] ": the SYNOPSIS shows " f ", which " rel(header) " does not declare (no RAY_API " f "): remove it from the page, or correct its name")
    }
    for (k = 1; k <= nm_count; k++) {
        f = nm_list[k]; p = page_of(nm_page[k])
        if (!(f in h_line))
            problem(rel(nm_page[k]) ":" nm_line[k] ": the NAME section lists " f ", which " rel(header) " does not declare: remove it (it would be installed as a link to " p ".3)")
        else if (!((p, f) in syn))
            problem(rel(nm_page[k]) ":" nm_line[k] ": the NAME section lists " f ", but the SYNOPSIS does not show its prototype")
    }
    for (k = 1; k <= page_count; k++) {
        file = pages[k]; p = page_of(file)
        if (!((p, p) in syn))
            problem(rel(file) ": the page is named after " p ", which is not in its SYNOPSIS" ((p in h_line) ? "" : " nor declared in " rel(header)) ": rename the page after one of its functions")
        want = toupper(p) " 3"
        if (dt[file] != want)
            problem(rel(file) ": its title line should be \".Dt " want "\", not \".Dt " dt[file] "\"")
    }
    for (k = 1; k <= link_count; k++) {
        f = links[k]
        if (!(f in m_page) || m_page[f] != link_page[f])
            problem("the Makefile MLINKS link " f ".3 -> " link_page[f] ".3, but " f " is " ((f in m_page) ? "documented on " m_page[f] ".3" : "in no SYNOPSIS"))
    }
    for (k = 1; k <= xref_count; k++) {
        f = xref[k]
        if (!(f in m_page))
            problem(xref_where[k] ": .Xr " f " 3 refers to a page that is not installed (no page or link of that name)")
    }
    for (k = 1; k <= type_count; k++) {
        t = types[k]
        if (!(t in mentioned))
            problem(rel(header) ":" type_line[t] ": the public type " t " is mentioned in no man page: document it on the page of the functions that use it")
    }

    for (k = 1; k <= const_count; k++) {
        t = consts[k]
        if (!(t in mentioned))
            problem(rel(header) ":" const_line[t] ": the public constant " t " is mentioned in no man page: document it where it is used")
    }

    if (problems) {
        print "docs-test: " problems " problem(s); include/ray.h is the reference: correct the man page (or the header, if the header is what is wrong)"
        exit 1
    }
    print "docs-test: " h_count " functions (RAY_API and static inline ray_*) of " rel(header) ", each with the same prototype in one SYNOPSIS of " page_count " pages in man/man3 and in its NAME section" (links_given ? ", " link_count " of them installed as links to the page" : "") "; " type_count " public types and " const_count " constants, each named in some page; " shown_count " ray.h types and enums copied into pages, each declaring the same members"
}
' "$header" $pages3 $pages7
