#!/usr/bin/env bash
# The sanitizer job: builds the readers, the fuzz harnesses and the fast
# unit suites over them (core, io, bags, command lines) with clang,
# AddressSanitizer and UndefinedBehaviorSanitizer (not the whole tree), runs
# the suites, then each harness for LISTA_FUZZ_SECONDS (default 60) from a
# copy of its seed corpus in fuzz/corpus/. A crash, a
# sanitizer report, an input slower than 10 s or one taking over 2 GB fails
# the job; libFuzzer leaves the input as crash-*/timeout-*/oom-* in the
# work folder, whose path is printed.
#   fuzz/run.sh [build-dir]        (default build-fuzz)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build-fuzz}
SECONDS_EACH=${LISTA_FUZZ_SECONDS:-60}
SAN="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLISTA_FUZZ=ON -DLISTA_BUILD_TESTS=ON \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS="$SAN -fsanitize=fuzzer-no-link" -DCMAKE_C_FLAGS="$SAN" \
  -DCMAKE_EXE_LINKER_FLAGS="$SAN" -DCMAKE_SHARED_LINKER_FLAGS="$SAN" >/dev/null
cmake --build "$BUILD" --target lista_fuzzers lista_sanitizer_suites -j "$(nproc)"

WORK=$(mktemp -d "${TMPDIR:-/tmp}/lista-fuzz.XXXXXX")
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
status=0
for suite in test_core test_lista_io test_lista_ros2bag test_lista_bag test_cli_parse; do
  echo "sanitizers: $suite" >&2
  if ! "$BUILD/bin/$suite" --gtest_brief=1 >"$WORK/$suite.log" 2>&1; then
    echo "sanitizers: $suite FAILED; its log: $WORK/$suite.log" >&2
    tail -40 "$WORK/$suite.log" >&2
    status=1
  fi
done
for pair in pcd:pcd ply:ply bin:bin poses:poses report:report ground_truth:ground_truth pipeline:pipeline \
            cdr:cdr mcap:mcap ros1bag:ros1bag; do
  harness=fuzz_${pair%%:*}
  corpus="$WORK/${pair#*:}"
  mkdir -p "$corpus"
  cp fuzz/corpus/"${pair#*:}"/* "$corpus"/
  echo "fuzz: $harness for ${SECONDS_EACH} s" >&2
  if ! (cd "$WORK" && TMPDIR="$WORK" "$OLDPWD/$BUILD/fuzz/$harness" -max_total_time="$SECONDS_EACH" -timeout=10 \
        -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 "$corpus" >"$WORK/$harness.log" 2>&1); then
    echo "fuzz: $harness FAILED; its log and the input: $WORK" >&2
    tail -40 "$WORK/$harness.log" >&2
    status=1
  else
    grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$WORK/$harness.log" | tr '\n' ' ' >&2
    echo >&2
  fi
done
[ "$status" = 0 ] && rm -rf "$WORK"
exit "$status"
