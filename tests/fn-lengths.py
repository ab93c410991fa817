"""Longest functions of Rust sources (outside `mod tests`): lines from `fn` to the
closing brace, counted on the text with string and char literals and comments
removed. Usage: python3 fnlen.py DIR... [-n N]"""
import os, re, sys

def strip(text):
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith('//', i):
            j = text.find('\n', i); i = n if j < 0 else j; continue
        if text.startswith('/*', i):
            j = text.find('*/', i); seg = text[i:j + 2]; out.append('\n' * seg.count('\n')); i = j + 2; continue
        m = re.match(r'b?r(#*)"', text[i:i + 12])
        if m and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == '_')):
            end = '"' + m.group(1); j = text.find(end, i + m.end()); seg = text[i:j + len(end)]
            out.append('""' + '\n' * seg.count('\n')); i = j + len(end); continue
        if c == '"':
            j = i + 1
            while text[j] != '"':
                j += 2 if text[j] == '\\' else 1
            out.append('""' + '\n' * text[i:j].count('\n')); i = j + 1; continue
        m = re.match(r"b?'(\\.[^']*|[^'\\])'", text[i:i + 12])
        if m and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == '_')):
            out.append("' '"); i += m.end(); continue
        out.append(c); i += 1
    return ''.join(out)

def lengths(path):
    lines = strip(open(path).read()).split('\n')
    i = 0
    while i < len(lines):
        if re.match(r'\s*(#\[cfg\(test\)\]\s*)?mod tests\b', lines[i]):
            return
        m = re.match(r'\s*(pub(\([^)]*\))?\s+)?(const\s+)?(unsafe\s+)?fn\s+(\w+)', lines[i])
        if not m:
            i += 1; continue
        depth, started, j = 0, False, i
        while j < len(lines):
            depth += lines[j].count('{') - lines[j].count('}')
            started = started or '{' in lines[j]
            if (started and depth <= 0) or (not started and lines[j].rstrip().endswith(';')):
                break
            j += 1
        if started:
            yield j - i + 1, m.group(5)
        i = j + 1

args = sys.argv[1:]
top = 8
if '-n' in args:
    k = args.index('-n'); top = int(args[k + 1]); del args[k:k + 2]
rows = []
for root in args:
    for dp, _, files in os.walk(root):
        if '/target' in dp:
            continue
        for f in files:
            if f.endswith('.rs'):
                p = os.path.join(dp, f)
                rows += [(n, p, name) for n, name in lengths(p)]
for n, p, name in sorted(rows, reverse=True)[:top]:
    print(n, p, name)
