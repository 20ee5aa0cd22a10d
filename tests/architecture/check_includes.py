#!/usr/bin/env python3
"""The module arrows of docs/architecture.md, checked on the source tree: each module's
sources (include/ and src/) include project headers only of the modules it may use, and
Simbody only inside model/src. Prints every violation as FILE:LINE: ... and exits 1 if
there is one."""
import pathlib
import re
import sys

ALLOWED = {
    "base": set(),
    "blocks": {"base"},
    "diagrams": {"base", "blocks"},
    "codegen": {"base", "blocks", "diagrams"},
    "model": {"base"},
    "viz": {"base"},
    "wholebody": {"base"},
    "sim": {"base", "blocks", "diagrams", "codegen", "model", "wholebody"},
    "report": {"base", "blocks", "diagrams", "codegen", "model", "sim", "viz"},
    "python": {"base", "blocks", "diagrams", "codegen", "model", "sim"},
}
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]dmbd/([a-z_]+)/')
SIMBODY = re.compile(r'^\s*#\s*include\s*[<"](Simbody\.h|simbody/|SimTKcommon)')


def main(root: pathlib.Path) -> int:
    bad = []
    for module, allowed in ALLOWED.items():
        for path in sorted((root / module).rglob("*")):
            if path.suffix not in (".hpp", ".cpp", ".h"):
                continue
            rel = path.relative_to(root)
            for n, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
                m = INCLUDE.match(line)
                if m and m.group(1) not in allowed | {module}:
                    bad.append(f"{rel}:{n}: {module} includes dmbd/{m.group(1)}/ (may use: {', '.join(sorted(allowed)) or 'nothing'})")
                if SIMBODY.match(line) and not str(rel).startswith("model/src/"):
                    bad.append(f"{rel}:{n}: Simbody outside model/src")
    for b in bad:
        print(b)
    print(f"{len(bad)} violation(s) of the module arrows" if bad else "module arrows: all includes allowed")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(pathlib.Path(sys.argv[1])))
