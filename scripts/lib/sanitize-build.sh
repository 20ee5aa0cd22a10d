# Sourced by scripts/sanitize and scripts/fuzz: configures build-sanitize/, one clang build
# with AddressSanitizer and UndefinedBehaviorSanitizer on every library (assertions on,
# -O1 -g), libFuzzer's coverage instrumentation (fuzzer-no-link), the tests and the fuzz
# targets (DMBD_FUZZ). One build serves both: the tests under the sanitizers, and the
# fuzzers. Warnings are not errors here (the Release build is the warning-free one).
sanitize_dir=build-sanitize
sanitize_flags="-fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=all -fno-omit-frame-pointer"
sanitize_configure() {
  for tool in clang++ llvm-symbolizer; do
    command -v "$tool" >/dev/null || { echo "$0: $tool not found (scripts/setup installs clang and llvm)" >&2; exit 2; }
  done
  [ -f "$sanitize_dir/build.ninja" ] && return 0
  # No Python module: an instrumented extension cannot load into Debian's uninstrumented
  # python3 (the sanitizers' runtime must come first in the process).
  CC=clang CXX=clang++ cmake -S . -B "$sanitize_dir" -G Ninja -DDMBD_FUZZ=ON -DBUILD_TESTING=ON -DDMBD_BENCH=OFF -DDMBD_PYTHON=OFF \
    -DDMBD_WERROR=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS="$sanitize_flags" \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
}
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
