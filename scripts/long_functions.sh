#!/usr/bin/env bash
# Lists the Rust functions longer than LIMIT lines (default 150) under DIR (default src/), longest
# first: "lines file:line name". Exits 1 when there is one, so CI can use it as a check.
# A function runs from its `fn` line to its closing brace; braces in strings, raw strings, chars
# and comments are skipped. Usage: scripts/long_functions.sh [LIMIT] [DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
exec python3 - "${1:-150}" "${2:-src}" <<'PY'
import os, re, sys

limit, root = int(sys.argv[1]), sys.argv[2]
FN = re.compile(r'\bfn\s+([A-Za-z_][A-Za-z0-9_]*)')

def code_only(src):
    """The source with strings, chars and comments blanked (newlines kept)."""
    out, i, n = [], 0, len(src)
    while i < n:
        c = src[i]
        if src.startswith('//', i):
            j = src.find('\n', i)
            j = n if j < 0 else j
            out.append(' ' * (j - i)); i = j
        elif src.startswith('/*', i):
            depth, j = 1, i + 2
            while j < n and depth:
                if src.startswith('/*', j): depth += 1; j += 2
                elif src.startswith('*/', j): depth -= 1; j += 2
                else: j += 1
            out.append(re.sub(r'[^\n]', ' ', src[i:j])); i = j
        elif (m := re.match(r'b?r(#*)"', src[i:i + 300])) and (i == 0 or not (src[i - 1].isalnum() or src[i - 1] == '_')):
            end = '"' + m.group(1)
            j = src.find(end, i + m.end())
            j = n if j < 0 else j + len(end)
            out.append(re.sub(r'[^\n]', ' ', src[i:j])); i = j
        elif c == '"':
            j = i + 1
            while j < n and src[j] != '"':
                j += 2 if src[j] == '\\' else 1
            j += 1
            out.append(re.sub(r'[^\n]', ' ', src[i:j])); i = j
        elif c == "'" and (m := re.match(r"'(\\.[^']*|[^\\'])'", src[i:i + 12])):
            out.append(' ' * m.end()); i += m.end()
        else:
            out.append(c); i += 1
    return ''.join(out)

found = []
for dirpath, _, files in os.walk(root):
    for f in sorted(files):
        if not f.endswith('.rs'):
            continue
        path = os.path.join(dirpath, f)
        code = code_only(open(path, encoding='utf-8').read())
        for m in FN.finditer(code):
            brace, semi = code.find('{', m.end()), code.find(';', m.end())
            if brace < 0 or (0 <= semi < brace):
                continue  # a declaration without a body
            depth, j = 0, brace
            while j < len(code):
                if code[j] == '{': depth += 1
                elif code[j] == '}':
                    depth -= 1
                    if depth == 0: break
                j += 1
            first = code.count('\n', 0, m.start()) + 1
            lines = code.count('\n', m.start(), j) + 1
            if lines > limit:
                found.append((lines, f'{path}:{first}', m.group(1)))
for lines, where, name in sorted(found, reverse=True):
    print(f'{lines:5} {where} {name}')
sys.exit(1 if found else 0)
PY
