#!/usr/bin/env python3
"""Lists C++ function bodies longer than a limit (default 100 lines) in the folders on a frame's
path. A body is counted from the line of its opening brace to the line of its closing brace.

Usage: check_function_length.py [--limit N] [ROOT]   (ROOT: the project folder, default .)
Exit status 0 when every body is within the limit, 1 otherwise (each offender printed as
file:line: name: N lines).

The parser is deliberately small: it strips comments and string literals, then treats a '{' as a
function body when the text before it (since the previous ';', '{' or '}') ends in a parameter
list, optionally followed by qualifiers or a constructor's initialiser list, and does not start
with a control keyword. Lambdas are counted inside the function that holds them.
"""
import argparse
import os
import re
import sys

FOLDERS = ["apps", "modules/slam", "filters", "registration", "surface", "modules/humans", "modules/detection"]
CONTROL = re.compile(r"^\s*(if|for|while|switch|catch|do|else|return|namespace|class|struct|enum|union)\b")
SIGNATURE = re.compile(r"\)\s*(const)?\s*(noexcept)?\s*(override|final)?\s*(->\s*[\w:<>,\s*&]+)?\s*(:.*)?$", re.S)


def strip(text):
    """Comments and string/char literals replaced by spaces, newlines kept."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(" " * (min(j, n - 1) - i + 1))
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def long_functions(path, limit):
    text = strip(open(path, encoding="utf-8", errors="replace").read())
    stack = []  # (is_function, start_line, name)
    head_start = 0
    found = []
    line = 1
    for i, c in enumerate(text):
        if c == "\n":
            line += 1
        elif c == "{":
            head = text[head_start:i]
            is_function = bool(SIGNATURE.search(head.strip())) and not CONTROL.match(head) \
                and not any(f for f, _, _ in stack)
            name = re.sub(r"\s+", " ", head.strip().split("(")[0])[-60:]
            stack.append((is_function, line, name))
            head_start = i + 1
        elif c == "}":
            if stack:
                is_function, start, name = stack.pop()
                if is_function and line - start + 1 > limit:
                    found.append((start, name, line - start + 1))
            head_start = i + 1
        elif c == ";":
            head_start = i + 1
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--limit", type=int, default=100)
    parser.add_argument("root", nargs="?", default=".")
    args = parser.parse_args()
    offenders = 0
    for folder in FOLDERS:
        for dirpath, _, files in sorted(os.walk(os.path.join(args.root, folder))):
            for f in sorted(files):
                if not f.endswith((".cpp", ".h", ".hpp", ".cc")):
                    continue
                path = os.path.join(dirpath, f)
                for start, name, length in long_functions(path, args.limit):
                    print(f"{os.path.relpath(path, args.root)}:{start}: {name}: {length} lines")
                    offenders += 1
    if offenders:
        print(f"{offenders} function bod{'y' if offenders == 1 else 'ies'} longer than {args.limit} lines")
        return 1
    print(f"every function body on the frame's path is within {args.limit} lines")
    return 0


if __name__ == "__main__":
    sys.exit(main())
