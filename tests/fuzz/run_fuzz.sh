#!/bin/sh
# SPDX-License-Identifier: LGPL-2.1-or-later
# Builds the libFuzzer target for point classification into build-fuzz/ and runs it for $1 seconds (default 30; nightly/long run: tests/fuzz/run_fuzz.sh 3600).
#
# Usage: tests/fuzz/run_fuzz.sh [seconds] [extra libFuzzer args...]
#   e.g. tests/fuzz/run_fuzz.sh 3600 -jobs=2 -workers=2
# Exits non-zero when the build fails or the fuzzer finds a crash / failed check;
# the crashing input is then in build-fuzz/artifacts/ (reproduce with
# build-fuzz/fuzz_pointclass build-fuzz/artifacts/crash-...).
set -eu

SECONDS_TO_RUN=${1:-30}
[ $# -gt 0 ] && shift

ROOT=$(cd "$(dirname "$0")/../.." && pwd)
OUT="$ROOT/build-fuzz"
CC=${CC:-clang}
mkdir -p "$OUT/corpus" "$OUT/artifacts"

# -ffp-contract=off: the exact predicates rely on every double operation rounding once.
# FUZZ_CFLAGS: extra compiler flags.
# shellcheck disable=SC2086
"$CC" -g -O1 -ffp-contract=off -fno-fast-math -fno-omit-frame-pointer ${FUZZ_CFLAGS:-} \
    -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
    -I"$ROOT/libcore/include" -I"$ROOT/libcore/src" \
    "$ROOT"/libcore/src/*.c "$ROOT/tests/fuzz/fuzz_pointclass.c" -lm \
    -o "$OUT/fuzz_pointclass"

SEEDS="$ROOT/tests/fuzz/corpus"
if [ ! -d "$SEEDS" ] || [ -z "$(ls -A "$SEEDS" 2>/dev/null)" ]; then
    python3 "$ROOT/tests/fuzz/make_seeds.py" "$SEEDS"
fi

# New inputs go to build-fuzz/corpus (the first directory); the committed seeds stay as they are.
exec "$OUT/fuzz_pointclass" "$OUT/corpus" "$SEEDS" \
    -max_total_time="$SECONDS_TO_RUN" -timeout=20 -rss_limit_mb=2048 -max_len=4096 \
    -artifact_prefix="$OUT/artifacts/" -print_final_stats=1 "$@"
