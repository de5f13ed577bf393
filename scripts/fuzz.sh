#!/usr/bin/env bash
# Longer fuzzing campaign (issue "Hardening"): runs the two proptest fuzz harnesses in release,
#   tests/tests/fuzz_scenes.rs  mutated scene TOML through parse, count, build, set-up and solve
#                               (lopin-core, in process),
#   app/tests/fuzz_cli.rs       random `lopin run|estimate|sweep` command lines on the real binary,
# with LOPIN_FUZZ_CASES cases each (default 400; CI's `cargo test` runs 64 and 24), all under a
# wall-clock bound of LOPIN_FUZZ_SECONDS (default 600): each harness runs under `timeout` of half
# of it. The harnesses also stop drawing new cases a margin before their half is over (through
# LOPIN_FUZZ_BUDGET_SECONDS), so a campaign ends cleanly with its report rather than killed.
# The generators are seeded: a failure reproduces by running again with the same
# LOPIN_FUZZ_SEED (unset: each harness's fixed default seed). Builds first, outside the bound,
# with the whole workspace's features (`--workspace`, as the README's test command builds), so
# after that command nothing is compiled again.
#
#   scripts/fuzz.sh                                  # 400 cases each, at most 600 s in all
#   LOPIN_FUZZ_CASES=2000 LOPIN_FUZZ_SECONDS=1800 LOPIN_FUZZ_SEED=7 scripts/fuzz.sh
#
# Exit status: 0 when both pass; otherwise the first failing harness's (124: the time bound).
set -uo pipefail
cd "$(dirname "$0")/.."

export LOPIN_FUZZ_CASES="${LOPIN_FUZZ_CASES:-400}"
total="${LOPIN_FUZZ_SECONDS:-600}"
seconds=$(( total / 2 > 1 ? total / 2 : 1 ))
margin=$(( seconds / 10 > 60 ? 60 : seconds / 10 ))
# stop drawing cases early enough for the last one (up to 60 s) and the report to fit
budget=$(( seconds - margin - 60 > 0 ? seconds - margin - 60 : seconds / 2 ))
export LOPIN_FUZZ_BUDGET_SECONDS="${LOPIN_FUZZ_BUDGET_SECONDS:-$budget}"

targets=(
    "--workspace ${LOPIN_FEATURES:-} --test fuzz_scenes"
    "--workspace ${LOPIN_FEATURES:-} --test fuzz_cli"
)

for t in "${targets[@]}"; do
    # shellcheck disable=SC2086  # $t holds several arguments
    cargo test --release $t --no-run || exit $?
done

status=0
for t in "${targets[@]}"; do
    echo "== fuzz: cargo test --release $t ($LOPIN_FUZZ_CASES cases, at most ${seconds} s)"
    start=$(date +%s)
    # shellcheck disable=SC2086
    timeout --kill-after=10 "$seconds" cargo test --release $t -- --nocapture
    rc=$?
    echo "== fuzz: $t: exit $rc after $(( $(date +%s) - start )) s"
    if [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; then
        echo "== fuzz: $t ran past ${seconds} s" >&2
    fi
    if [ "$status" -eq 0 ] && [ "$rc" -ne 0 ]; then
        status=$rc
    fi
done
exit "$status"
