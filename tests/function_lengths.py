#!/usr/bin/env python3
"""No function over 80 lines without a reason (README, "Code style"; docs/architecture.md).

A function's body is counted from the line of its opening brace to the line of its closing
one; a TEST is a function. A body longer than the limit must have a comment right above its
definition that says why it is one piece, starting "Over 80 lines on purpose:" (a table of
entries, one random sequence).
Comments and string literals are blanked before the braces are matched; lambdas and local
classes count as part of the function they stand in.

usage: function_lengths.py SOURCE_DIR [LIMIT]   (exit 1 listing each long function without a
comment; every long function is printed)
"""
import pathlib
import re
import sys

FOLDERS = ("src", "include", "python", "tests", "tools")
SUFFIXES = (".cpp", ".hpp", ".h", ".cc")
NOT_FUNCTIONS = {"if", "for", "while", "switch", "catch", "return", "sizeof", "decltype",
                 "alignas", "static_assert", "noexcept"}
# The end of a function head: name(arguments) [const] [noexcept] [override] [final] [-> type]
# [: member initialisers], right before its '{'.
HEAD = re.compile(
    r"(\b[\w:~<>]+)\s*\((?:[^()]|\([^()]*\))*\)\s*(?:const\s*)?(?:noexcept\s*)?"
    r"(?:override\s*)?(?:final\s*)?(?:->\s*[\w:<>&*, ]+)?\s*(?::[^;{}]*)?$", re.S)
RAW_STRING = re.compile(r'R"([^(]*)\(')


def blank(text):
    """The text with comments and string and character literals emptied, lines kept."""
    out, i, n = [], 0, len(text)
    while i < n:
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
            continue
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
            continue
        raw = RAW_STRING.match(text, i)
        if raw:
            end = ")" + raw.group(1) + '"'
            j = text.find(end, raw.end())
            j = n if j < 0 else j + len(end)
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j
            continue
        c = text[i]
        if c == '"' or (c == "'" and not (i > 0 and text[i - 1].isalnum())):
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
            continue
        out.append(c)
        i += 1
    return "".join(out)


def head_before(lines, line, column):
    """The statement text before a brace: back to the last ';', '{' or '}'."""
    chunk, k = lines[line][:column], line - 1
    while len(chunk) < 400 and k >= 0:
        chunk = lines[k] + "\n" + chunk
        k -= 1
    cut = max(chunk.rfind(";"), chunk.rfind("{"), chunk.rfind("}"))
    return chunk[cut + 1:].strip()


def function_name(head):
    """The function a '{' opens, or None (a block, a class, an initialiser)."""
    m = HEAD.search(head)
    if not m or m.group(1) in NOT_FUNCTIONS:
        return None
    if m.group(1).startswith("TEST"):
        t = re.search(r"TEST\w*\s*\(\s*(\w+)\s*,\s*(\w+)", head)
        return f"{t.group(1)}.{t.group(2)}" if t else m.group(1)
    return m.group(1)


def long_functions(path, limit):
    """(length, first line, name) of every function body of `path` longer than `limit`."""
    lines = blank(path.read_text(errors="replace")).split("\n")
    stack, found = [], []
    for number, line in enumerate(lines):
        for column, ch in enumerate(line):
            if ch == "{":
                inside = any(name for name, _ in stack)
                name = None if inside else function_name(head_before(lines, number, column))
                stack.append((name, number))
            elif ch == "}" and stack:
                name, first = stack.pop()
                if name and number - first + 1 > limit:
                    found.append((number - first + 1, first, name))
    return found


COMMENT = ("//", "/*", "*")
REASON = re.compile(r"over \d+ lines", re.I)


def has_reason(source_lines, first):
    """Whether the comment right above the definition whose brace is on line `first` gives
    the reason for its length."""
    k = first
    while k >= 0 and not source_lines[k].strip().startswith(COMMENT):
        if k < first and (not source_lines[k].strip()
                          or source_lines[k].rstrip().endswith((";", "}"))):
            return False
        k -= 1
    comment = []
    while k >= 0 and source_lines[k].strip().startswith(COMMENT):
        comment.append(source_lines[k])
        k -= 1
    return bool(REASON.search(" ".join(comment)))


def main():
    root = pathlib.Path(sys.argv[1])
    limit = int(sys.argv[2]) if len(sys.argv) > 2 else 80
    missing = 0
    for folder in FOLDERS:
        for path in sorted((root / folder).rglob("*")):
            if path.suffix not in SUFFIXES or "build" in path.relative_to(root).parts:
                continue
            source = path.read_text(errors="replace").split("\n")
            for length, first, name in long_functions(path, limit):
                ok = has_reason(source, first)
                missing += not ok
                where = path.relative_to(root)
                print(f"{where}:{first + 1}: {name}: {length} lines"
                      + ("" if ok else f", over {limit} without a comment saying why "
                                       f"(\"Over {limit} lines on purpose: ...\")"))
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
