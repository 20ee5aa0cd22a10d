#!/usr/bin/env python3
"""The module arrows of docs/architecture.md, checked on the source tree: each module's
sources (include/ and src/) include project headers only of the modules it may use, and
Simbody only inside model/src; and robots are data: no library source names a robot in
a string ("draco" outside comments and the product's name draco-mbd) or calls a robot's
own folder function. Prints every violation as FILE:LINE: ... and exits 1 if there is
one."""
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
    "sim": {"base", "blocks", "diagrams", "codegen", "model"},
    "control": {"base", "model", "wholebody", "sim"},
    "experiments": {"base", "blocks", "model", "wholebody", "sim", "control"},
    "scenario": {"base", "blocks", "diagrams", "codegen", "model", "sim", "control", "experiments"},
    "report": {"base", "blocks", "diagrams", "codegen", "model", "wholebody", "sim", "control", "experiments", "scenario", "viz"},
    "python": {"base", "blocks", "diagrams", "codegen", "model", "wholebody", "sim", "control", "experiments", "scenario"},
    "apps": {"base", "blocks", "diagrams", "codegen", "model", "wholebody", "sim", "control", "experiments", "scenario", "viz", "report"},
}
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]dmbd/([a-z_]+)/')
SIMBODY = re.compile(r'^\s*#\s*include\s*[<"](Simbody\.h|simbody/|SimTKcommon)')
ROBOT = re.compile(r'"[^"\n]*\bdraco\b(?!-mbd)[^"\n]*"|\bdraco_dir\b', re.IGNORECASE)


def code_of(line: str) -> str:
    """The line without its // comment (a // inside a string literal kept)."""
    out, quoted = [], False
    for k, c in enumerate(line):
        if c == '"' and (k == 0 or line[k - 1] != "\\"):
            quoted = not quoted
        if not quoted and line.startswith("//", k):
            break
        out.append(c)
    return "".join(out)


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
                if ROBOT.search(code_of(line)):
                    bad.append(f"{rel}:{n}: a robot named in library code (robots are data: robots/NAME/)")
    for b in bad:
        print(b)
    print(f"{len(bad)} violation(s) of the module arrows" if bad else "module arrows: all includes allowed")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(pathlib.Path(sys.argv[1])))
