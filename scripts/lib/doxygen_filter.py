#!/usr/bin/env python3
"""Doxygen INPUT_FILTER (docs/api/Doxyfile): the project's headers document themselves
in plain // comments; this hands them to Doxygen as documentation without rewriting the
sources. A header's opening comment block (after `#pragma once`) becomes the file's
description (the pragma's line becomes `/// @file`), a comment line before a declaration
documents it (///), a comment after code on the same line documents that member (///<).
Lines keep their numbers, so Doxygen's warnings point at the real lines. In the
comments' text outside `code` spans, \\ < > @ # are escaped: prose such as <name>.hpp is
not HTML."""
import re
import sys

LEADING = re.compile(r'^(\s*)//(?!/)\s?(.*)$')
TRAILING = re.compile(r'^(\s*[^\s/].*?[;,{)}]\s*)//(?!/)\s?(.*)$')


def escape(text):
    """Characters Doxygen would read as commands or HTML in prose: \\ < > @ #, taken
    literally outside `code` spans (which Doxygen already shows as they are); markdown
    and indented formula blocks are kept."""
    parts = re.split(r'(`[^`]*`)', text)
    return ''.join(p if p.startswith('`') and p.endswith('`') and len(p) > 1
                   else re.sub(r'([\\<>@#])', r'\\\1', p) for p in parts)


def convert(lines):
    out = []
    for i, line in enumerate(lines):
        body = line.rstrip('\n')
        if i == 0 and body.strip() == '#pragma once' and len(lines) > 1 and LEADING.match(lines[1].rstrip('\n')):
            out.append('/// @file')
            continue
        m = LEADING.match(body)
        if m:
            out.append(f'{m.group(1)}/// {escape(m.group(2))}')
            continue
        t = TRAILING.match(body)
        if t and '"' not in t.group(1):
            out.append(f'{t.group(1)}///< {escape(t.group(2))}')
            continue
        out.append(body)
    return out


def main():
    with open(sys.argv[1], encoding='utf-8') as f:
        lines = f.readlines()
    sys.stdout.write('\n'.join(convert(lines)) + '\n')


if __name__ == '__main__':
    main()
