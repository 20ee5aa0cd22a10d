#!/usr/bin/env python3
"""Issue 28 row 15: every test ctest lists has a readable, stable name. A parameterised
test whose parameter gtest cannot print shows its raw bytes ("GetParam() = 120-byte object
<F0-4A ...>", pointers included, so different in every build); such a test needs a PrintTo
(or a name generator). Usage: check_test_names.py CTEST BUILD_DIR"""
import re
import subprocess
import sys

ctest, build = sys.argv[1], sys.argv[2]
listing = subprocess.run([ctest, "-N"], cwd=build, capture_output=True, text=True, check=True).stdout
names = [l for l in listing.splitlines() if re.match(r"\s*Test\s+#\d+:", l)]
raw = [l.strip() for l in names if re.search(r"\d+-byte object <", l)]
if len(names) < 100:
    sys.exit(f"only {len(names)} tests listed by ctest -N in {build}: is the build complete?")
if raw:
    print(f"{len(raw)} test names carry a parameter's raw bytes (give its type a PrintTo):", file=sys.stderr)
    for l in raw[:20]:
        print("  " + l, file=sys.stderr)
    sys.exit(1)
print(f"{len(names)} test names, none with raw bytes")
