#!/bin/sh
# SPDX-License-Identifier: LGPL-2.1-or-later
# Builds the libFuzzer targets (point classification; the raw C API of every entry point;
# the properties of rotational sweep results, fuzz_sweep.c) into build-fuzz/ and runs them.
#
# Usage: tests/fuzz/run_fuzz.sh [seconds] [extra libFuzzer args...]
#   e.g. tests/fuzz/run_fuzz.sh 3600 -jobs=2 -workers=2
# Two modes, by the time given:
#  - up to 60 s (CI: tests/run_all.sh runs 30): deterministic.  Each target runs a fixed
#    number of inputs, 150 per second given (30: 4500 each; MFG_FUZZ_RUNS sets it), from
#    a fixed -seed, starting from the committed seeds only (a fresh work corpus), with
#    address randomisation off (setarch -R: the targets compare pointers, and libFuzzer
#    learns from compared values).  So a CI run of one tree always explores the same
#    inputs: it goes red on a regression, never on a new path found by luck.  The time
#    is only a generous cap (10x) against hangs.
#  - longer (nightly / exploration: tests/fuzz/run_fuzz.sh 3600): random seed, the time
#    split evenly between the targets, new inputs kept in the work corpus.
# MFG_FUZZ_OUT=dir builds and works in dir instead of build-fuzz/.
# Exits non-zero when a build fails or a fuzzer finds a crash / failed check; the
# crashing input is then in build-fuzz/artifacts/ (reproduce with
# build-fuzz/fuzz_pointclass build-fuzz/artifacts/crash-..., or fuzz_api for api-crash-...).
set -eu

SECONDS_TO_RUN=${1:-30}
[ $# -gt 0 ] && shift

ROOT=$(cd "$(dirname "$0")/../.." && pwd)
OUT=${MFG_FUZZ_OUT:-"$ROOT/build-fuzz"}
CC=${CC:-clang}
mkdir -p "$OUT/corpus" "$OUT/corpus_api" "$OUT/corpus_sweep" "$OUT/artifacts"

# -ffp-contract=off: the exact predicates rely on every double operation rounding once.
# FUZZ_CFLAGS: extra compiler flags.
for target in fuzz_pointclass fuzz_api fuzz_sweep; do
    # shellcheck disable=SC2086
    "$CC" -g -O1 -ffp-contract=off -fno-fast-math -fno-omit-frame-pointer ${FUZZ_CFLAGS:-} \
        -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
        -I"$ROOT/libcore/include" -I"$ROOT/libcore/src" -I"$ROOT/libcore/tests/sweep" \
        "$ROOT"/libcore/src/*/*.c "$ROOT/tests/fuzz/$target.c" -lm \
        -o "$OUT/$target"
done

seeds() {  # seeds DIR GENERATOR: the committed seeds, regenerated if missing
    if [ ! -d "$1" ] || [ -z "$(ls -A "$1" 2>/dev/null)" ]; then
        python3 "$ROOT/tests/fuzz/$2" "$1"
    fi
}
seeds "$ROOT/tests/fuzz/corpus" make_seeds.py
seeds "$ROOT/tests/fuzz/corpus_api" make_seeds_api.py

# The time budget is shared: half each (at least 1 s).
FIRST=$((SECONDS_TO_RUN / 2))
[ "$FIRST" -ge 1 ] || FIRST=1
SECOND=$((SECONDS_TO_RUN - FIRST))
[ "$SECOND" -ge 1 ] || SECOND=1

if [ "$SECONDS_TO_RUN" -le 60 ]; then
    # Deterministic (see the top): fixed seed and run count, fresh work corpora, no ASLR.
    RUNS=${MFG_FUZZ_RUNS:-$((150 * SECONDS_TO_RUN))}
    WORK=$(mktemp -d "${TMPDIR:-/tmp}/mfg_fuzz.XXXXXX")
    trap 'rm -rf "$WORK"' EXIT
    mkdir -p "$WORK/corpus" "$WORK/corpus_api" "$WORK/corpus_sweep"
    CORPUS=$WORK/corpus CORPUS_API=$WORK/corpus_api CORPUS_SWEEP=$WORK/corpus_sweep
    # fuzz_sweep checks results (two sweeps and ~10^2 winding numbers over the result
    # per input, ~0.2 s under the sanitizers): a fiftieth of the runs
    SWEEP_ARGS="-seed=1 -runs=$((RUNS / 50))"
    FIRST=$((10 * SECONDS_TO_RUN))
    SECOND=$FIRST
    MODE_ARGS="-seed=1 -runs=$RUNS"
    NOASLR="setarch $(uname -m) -R"
    $NOASLR true 2>/dev/null || {
        echo "run_fuzz.sh: setarch -R unavailable; address randomisation stays on (runs may differ)" >&2
        NOASLR=
    }
else
    CORPUS=$OUT/corpus CORPUS_API=$OUT/corpus_api CORPUS_SWEEP=$OUT/corpus_sweep
    SWEEP_ARGS=
    MODE_ARGS=
    NOASLR=
fi

# New inputs go to the work corpus (the first directory); the committed seeds stay as they are.
run() {  # run TARGET WORK_CORPUS SEEDS SECONDS PREFIX [args...]
    target=$1 work=$2 seeds=$3 secs=$4 prefix=$5
    shift 5
    # shellcheck disable=SC2086
    $NOASLR "$OUT/$target" "$work" "$seeds" $MODE_ARGS \
        -max_total_time="$secs" -timeout=20 -rss_limit_mb=2048 -max_len=4096 \
        -artifact_prefix="$OUT/artifacts/$prefix" -print_final_stats=1 "$@"
}
status=0
run fuzz_pointclass "$CORPUS" "$ROOT/tests/fuzz/corpus" "$FIRST" "" "$@" || status=1
run fuzz_api "$CORPUS_API" "$ROOT/tests/fuzz/corpus_api" "$SECOND" "api-" "$@" || status=1
MODE_ARGS=${SWEEP_ARGS:-$MODE_ARGS} run fuzz_sweep "$CORPUS_SWEEP" "$ROOT/tests/fuzz/corpus_sweep" "$SECOND" "sweep-" -max_len=64 "$@" || status=1
exit $status
