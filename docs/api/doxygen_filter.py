#!/usr/bin/env python3
"""Doxygen INPUT_FILTER: read usm's plain C comments as documentation.

The headers are documented in plain C comments (/* ... */), which Doxygen
skips.  This filter hands Doxygen a copy, line for line (warnings keep their
line numbers), in which
  - the file's opening comment becomes the file's documentation, verbatim;
  - a comment on lines of its own documents the declaration after it (/**);
  - a comment after code on the same line documents that member (/**<);
  - section rulers such as "/* ---- models ---- */" and comments on
    preprocessor lines other than #define stay plain comments;
  - Doxygen's special characters in comment text are escaped, outside
    `code spans`, so the text reads as written.
Usage: doxygen_filter.py FILE  (prints the filtered FILE)
"""
import re
import sys

RULER = re.compile(r"^\s*/\*\s*-{3,}.*\*/\s*$")
SPECIAL = re.compile(r"([\\@<>&#%$])")
DECORATION = re.compile(r"^\s*\* ?")
DIRECTIVE = re.compile(r"^\s*#\s*(?!define\b)\w")


def escape(text):
    """Escape Doxygen's special characters outside `code spans`."""
    parts = text.split("`")
    for i in range(0, len(parts), 2):  # even parts are outside backticks
        parts[i] = SPECIAL.sub(r"\\\1", parts[i])
    if len(parts) % 2 == 0:  # unbalanced backtick: leave it literal
        parts[-2] += "\\`" + parts.pop()
    return "`".join(parts)


def filter_lines(lines):
    out = []
    in_comment = False   # inside a comment converted to documentation
    in_plain = False     # inside a comment left as it is
    header_done = False  # the file's opening comment has been seen
    header = False       # inside the file's opening comment
    for line in lines:
        if in_comment or in_plain:
            end = line.find("*/")
            body, rest = (line, "") if end < 0 else (line[:end], line[end:])
            if header:  # verbatim: drop the " * " decoration
                body = DECORATION.sub("", body)
            elif in_comment:
                body = escape(body)
            if end >= 0:
                if header:
                    rest = "@endverbatim @file " + rest
                in_comment = in_plain = header = False
            out.append(body + rest)
            continue
        start = line.find("/*")
        if start < 0 or line.find("//", 0, start) >= 0:
            out.append(line)
            continue
        code, comment = line[:start], line[start + 2:]
        if not header_done and not code.strip() and not out:
            # The file's opening comment: verbatim, documents the file.
            header_done = True
            end = comment.find("*/")
            if end >= 0:  # one-line file comment
                out.append(code + "/** " + escape(comment[:end]) + " @file " + comment[end:])
            else:
                header = in_comment = True
                out.append(code + "/** @verbatim" + comment)
            continue
        header_done = True
        if (RULER.match(line) or comment.startswith("*") or comment.startswith("!")
                or DIRECTIVE.match(code)):
            # Rulers and comments on directives other than #define (such as
            # "#endif /* USM_H */") stay plain; /** and /*! are documentation already.
            if "*/" not in comment:
                in_plain = True
            out.append(line)
            continue
        marker = "/**< " if code.strip() else "/** "
        end = comment.find("*/")
        if end >= 0:
            out.append(code + marker + escape(comment[:end]) + comment[end:])
        else:
            in_comment = True
            out.append(code + marker + escape(comment))
    return out


def main():
    with open(sys.argv[1], encoding="utf-8") as f:
        text = f.read()
    lines = text.split("\n")
    sys.stdout.write("\n".join(filter_lines(lines)))


if __name__ == "__main__":
    main()
