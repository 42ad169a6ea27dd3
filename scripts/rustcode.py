"""What the source checkers (`scripts/module-cycles`, `scripts/long-functions`) read of a Rust
file: its code alone, without comments, string or character contents, or `#[cfg(test)]`
modules, with every line kept in its place (what is removed leaves its line breaks), so line
numbers still point into the file.

A hand scanner, not regular expressions: a string may span lines (a `\\` at a line's end, or a
raw string), hold `//` or `"` or braces, and a `'` starts a character literal or a lifetime;
a regular expression that missed one of these hid the code after it (issue 40).
"""
import os
import re


def _blank(text: str) -> str:
    """`text`'s line breaks, nothing else."""
    return "\n" * text.count("\n")


def strip_literals(text: str) -> str:
    """Code without comments (line, block, nested block, doc) and with every string, byte
    string, raw string and character literal emptied (`""`, `''`), line breaks kept."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        nxt = text[i + 1] if i + 1 < n else ""
        if c == "/" and nxt == "/":
            j = text.find("\n", i)
            i = n if j < 0 else j
            continue
        if c == "/" and nxt == "*":
            depth, j = 1, i + 2
            while j < n and depth:
                if text.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif text.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            out.append(_blank(text[i:j]))
            i = j
            continue
        # Raw strings: r"..", r#".."#, br"..", cr#".."# (not part of a longer identifier).
        m = re.compile(r'(?:b|c)?r(#*)"').match(text, i)
        if m and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            close = '"' + m.group(1)
            j = text.find(close, m.end())
            j = n if j < 0 else j + len(close)
            out.append('""' + _blank(text[i:j]))
            i = j
            continue
        if c == '"' or (c in "bc" and nxt == '"' and not (i and (text[i - 1].isalnum() or text[i - 1] == "_"))):
            j = i + (1 if c == '"' else 2)
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append('""' + _blank(text[i:j]))
            i = j
            continue
        if c == "'" or (c == "b" and nxt == "'" and not (i and (text[i - 1].isalnum() or text[i - 1] == "_"))):
            q = i if c == "'" else i + 1
            # A character literal: an escape, or one character then `'`; else a lifetime or
            # a label (`'a`, `'outer:`), which is code.
            if q + 1 < n and text[q + 1] == "\\":
                j = q + 2
                while j < n and text[j] != "'":
                    j += 2 if text[j] == "\\" else 1
                out.append("''")
                i = min(j + 1, n)
                continue
            if q + 2 < n and text[q + 2] == "'" and text[q + 1] != "\n":
                out.append("''")
                i = q + 3
                continue
        out.append(c)
        i += 1
    return "".join(out)


TEST_MODULE = re.compile(r"#\[cfg\(test\)\]\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+\w+\s*\{")
TEST_MODULE_FILE = re.compile(r"#\[cfg\(test\)\]\s*(?:#\[[^\]]*\]\s*)*(?:pub(?:\([^)]*\))?\s+)?mod\s+(\w+)\s*;")


def strip(text: str) -> str:
    """Code only: no comments, no string contents, no `#[cfg(test)] mod ... { }` blocks;
    line breaks kept."""
    text = strip_literals(text)
    out = []
    i = 0
    for m in TEST_MODULE.finditer(text):
        if m.start() < i:
            continue
        out.append(text[i:m.start()])
        depth = 1
        j = m.end()
        while j < len(text) and depth:
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            j += 1
        out.append(_blank(text[m.start():j]))
        i = j
    out.append(text[i:])
    return "".join(out)


def test_module_files(path: str, code: str):
    """The files of the `#[cfg(test)] mod name;` declarations of `path` (already stripped)."""
    base = os.path.dirname(path)
    stem = os.path.splitext(os.path.basename(path))[0]
    own = base if stem in ("lib", "main", "mod") else os.path.join(base, stem)
    found = []
    for name in TEST_MODULE_FILE.findall(code):
        for candidate in (os.path.join(own, name + ".rs"), os.path.join(own, name, "mod.rs")):
            if os.path.isfile(candidate):
                found.append(os.path.normpath(candidate))
    return found
