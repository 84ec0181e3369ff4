#!/usr/bin/env python3
"""No function over MAX_LINES lines in icobrdf/, cli/ and python/, unless a comment above it says why.

A function's length runs from the first line of its declaration (the line of its return type, template
header or name) to the line of its closing brace. The check finds function bodies by brace matching on the
C++ source with comments, string and character literals and preprocessor lines removed: a '{' at namespace
or class scope opens a function body when the text before it (since the last ';', '{' or '}') ends in a
parameter list, possibly followed by qualifiers (const, noexcept, override, -> type) or a constructor's
initializer list; a lambda passed to a namespace-scope object (a command registrar) counts as a function of
that object's name (so does a lambda argument of a namespace-scope call). Braces of class, struct, union, enum and namespace bodies are scopes, not functions;
every other brace (initializers) is skipped.

Exemption: a comment block directly above the declaration containing "Long function:" followed by the
reason (for example a genuinely linear sequence of steps that reads best in one piece).

Prints "file:line name length" for each offender and exits 1 if there is any; exits 0 otherwise.
Usage: check_function_length.py [REPO_ROOT] (default: two folders above this script).
"""
import pathlib
import re
import sys

MAX_LINES = 120  # the project's limit: a function longer than this is split into named helpers
FOLDERS = ("icobrdf", "cli", "python")
EXTENSIONS = {".cpp", ".hpp", ".h", ".cc"}
EXEMPTION = re.compile(r"Long function:\s*\S", re.IGNORECASE)
CLASS_KEYWORDS = re.compile(r"\b(class|struct|union|enum)\b")
NAMESPACE = re.compile(r"^(inline\s+)?namespace\b|^extern\s*\"\"\s*$")


def end_of_quoted(text, i):
    """The index after the string or character literal opening at text[i] (its quote), escapes skipped."""
    quote, j, n = text[i], i + 1, len(text)
    while j < n and text[j] != quote and text[j] != "\n":
        j += 2 if text[j] == "\\" else 1
    return j + 1


def strip_code(text):
    """Comments, string and character literals blanked (newlines kept), preprocessor lines emptied."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        nxt = text[i + 1] if i + 1 < n else ""
        if c == "/" and nxt == "/":
            while i < n and text[i] != "\n":
                i += 1
            continue
        if c == "/" and nxt == "*":
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:end]))
            i = end
            continue
        raw = re.match(r'(u8|u|U|L)?R"([^()\\\s]{0,16})\(', text[i:i + 24]) if c in "uULR" else None
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            close = ")" + raw.group(2) + '"'
            end = text.find(close, i + raw.end())
            end = n if end < 0 else end + len(close)
            out.append('""' + "".join("\n" for ch in text[i:end] if ch == "\n"))
            i = end
            continue
        if c == '"':
            out.append('""')
            i = end_of_quoted(text, i)
            continue
        if c == "'":
            prev = text[i - 1] if i > 0 else ""
            if prev.isalnum() and nxt.isalnum():  # digit separator: 20'000'000
                out.append(c)
                i += 1
                continue
            out.append("' '")
            i = end_of_quoted(text, i)
            continue
        out.append(c)
        i += 1
    lines = "".join(out).split("\n")
    continuing = False
    for k, line in enumerate(lines):
        if continuing or line.lstrip().startswith("#"):
            continuing = line.rstrip().endswith("\\")
            lines[k] = ""
    return lines


def top_level(header):
    """[(parenthesis depth, char)] of the header: an opening parenthesis at its inner depth, a closing one at
    its outer depth (so a top-level parameter list opens at depth 1 and closes at depth 0)."""
    depth, chars = 0, []
    for ch in header:
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth = max(0, depth - 1)
        chars.append((depth, ch))
    return chars


def classify(header):
    """'function', 'init' (a brace initializer inside a constructor's initializer list), 'scope' or 'other'."""
    h = " ".join(header.split())
    if not h:
        return "other"
    chars = top_level(h)
    flat = "".join(ch if d == 0 else "" for d, ch in chars)
    if NAMESPACE.search(h) and "(" not in h:
        return "scope"
    end_depth = chars[-1][0]
    if end_depth > 0:  # inside a call: a lambda argument, "name(..., [...](...) {"
        inner_close = max((k for k, (d, ch) in enumerate(chars) if ch == ")" and d == end_depth), default=-1)
        trailing = "".join(ch for _, ch in chars[inner_close + 1:])
        lambda_like = inner_close >= 0 and "]" in h and re.fullmatch(r"[\s\w&*<>:,\-]*", trailing)
        return "function" if lambda_like else "other"
    last_close = max((k for k, (d, ch) in enumerate(chars) if ch == ")" and d == 0), default=-1)
    if last_close >= 0:
        first_open = next((k for k, (d, ch) in enumerate(chars) if ch == "(" and d == 1), None)
        if first_open is None:
            return "other"
        before = "".join(ch for d, ch in chars[:first_open] if d == 0)
        trailing = "".join(ch for d, ch in chars[last_close + 1:] if d == 0)
        if "=" in before.replace("operator", "", 1) and "operator" not in before:
            return "other"
        if re.search(r"(^|[^:]):([^:]|$)", trailing):  # a constructor's initializer list
            return "init" if re.search(r"[\w>]\s*$", trailing) and not trailing.rstrip().endswith(("const", "noexcept", "override")) else "function"
        if "=" in trailing or ";" in trailing:
            return "other"
        if re.fullmatch(r"[\s\w&*<>:,\-\[\]]*", trailing):
            return "function"
        return "other"
    if CLASS_KEYWORDS.search(flat) and "=" not in flat:
        return "scope"
    return "other"


def function_name(header):
    h = " ".join(header.split())
    m = re.search(r"([~\w:]+(?:operator\s*\S+?)?)\s*(?:<[^()]*>)?\s*\(", h)
    return m.group(1) if m else "?"


def exempt(original_lines, start):
    k = start - 1
    while k >= 0 and original_lines[k].strip().startswith("//"):
        if EXEMPTION.search(original_lines[k]):
            return True
        k -= 1
    return False


def functions(path):
    """(line, name, length) of every function body at namespace or class scope in the file."""
    original = path.read_text(encoding="utf-8", errors="replace").split("\n")
    lines = strip_code("\n".join(original))
    found = []
    stack = []  # kinds of the open braces outside functions: 'scope', 'other', 'init'
    header, header_line = "", None
    in_function = None  # (start line, name, depth of the body's brace) while inside a function
    depth = 0
    for lineno, line in enumerate(lines):
        for ch in line:
            if in_function is not None:
                if ch == "{":
                    depth += 1
                elif ch == "}":
                    depth -= 1
                    if depth == in_function[2]:
                        start, name, _ = in_function
                        found.append((start, name, lineno - start + 1))
                        in_function = None
                        header, header_line = "", None
                continue
            if ch == "{":
                kind = classify(header)
                if kind == "function":
                    start = header_line if header_line is not None else lineno
                    in_function = (start, function_name(header), depth)
                    depth += 1
                    continue
                stack.append(kind)
                depth += 1
                if kind != "init":
                    header, header_line = "", None
                else:
                    header += "{"
            elif ch == "}":
                kind = stack.pop() if stack else "other"
                depth -= 1
                if kind == "init":
                    header += "}"
                else:
                    header, header_line = "", None
            elif ch == ";":
                header, header_line = "", None
            else:
                if header_line is None and not ch.isspace():
                    header_line = lineno
                if header_line is not None:
                    header += ch
        if header_line is not None:
            header += " "
    return [(start + 1, name, length, exempt(original, start)) for start, name, length in found]


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parents[2])
    offenders = []
    for folder in FOLDERS:
        for path in sorted((root / folder).rglob("*")):
            if path.suffix in EXTENSIONS and path.is_file():
                for line, name, length, is_exempt in functions(path):
                    if length > MAX_LINES and not is_exempt:
                        offenders.append(f"{path.relative_to(root)}:{line} {name} {length}")
    for o in offenders:
        print(o)
    if offenders:
        print(f"{len(offenders)} function(s) over {MAX_LINES} lines without a 'Long function:' comment saying why", file=sys.stderr)
    return 1 if offenders else 0


if __name__ == "__main__":
    sys.exit(main())
