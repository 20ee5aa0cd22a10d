#!/usr/bin/env python3
"""Build the API reference (Doxygen, docs/api/Doxyfile) into OUT/html and check it:
exit 1, listing them, when Doxygen warns about a header of the modules users call
(blocks, diagrams, codegen, sim, control, experiments, scenario: an undocumented public member or a malformed comment);
the other modules' warnings are counted, not failed. Run from anywhere:
    check_docs.py OUT"""
import os
import pathlib
import subprocess
import sys

CHECKED = ('blocks', 'diagrams', 'codegen', 'sim', 'control', 'experiments', 'scenario')


def main():
    root = pathlib.Path(__file__).resolve().parents[2]
    out = pathlib.Path(sys.argv[1]).resolve()
    out.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, DMBD_DOCS_OUT=str(out))
    subprocess.run(['doxygen', 'docs/api/Doxyfile'], cwd=root, env=env, check=True)
    counts, failing = {}, []
    for line in (out / 'warnings.log').read_text(encoding='utf-8').splitlines():
        if not line.strip():
            continue
        rel = line[len(str(root)) + 1:] if line.startswith(str(root)) else line
        module = rel.split('/', 1)[0]
        counts[module] = counts.get(module, 0) + 1
        if module in CHECKED:
            failing.append(rel)
    print(f'API reference: {out / "html" / "index.html"}')
    for module in sorted(counts):
        print(f'  {module}: {counts[module]} warning(s)' + ('' if module in CHECKED else ' (not checked)'))
    if failing:
        print(f'{len(failing)} warning(s) in {", ".join(CHECKED)}:', file=sys.stderr)
        for line in failing[:40]:
            print('  ' + line, file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
