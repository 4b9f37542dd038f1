#!/usr/bin/env bash
# expect.sh CODE PATTERN ABSENT CMD...: passes when CMD exits with CODE within 120 s, its output
# (stderr+stdout) matches PATTERN (grep -E) and does not match ABSENT ("" checks nothing).
# "internal error" is never accepted: issue 15 leaves none for anything a user can cause.
code=$1; pattern=$2; absent=$3; shift 3
start=$SECONDS
out=$(timeout 120 "$@" 2>&1); got=$?
took=$((SECONDS - start))
if [[ $got -ne $code ]]; then
  echo "expected exit $code, got $got after ${took}s from: $*"; echo "$out" | head -c 4000; exit 1
fi
if ! grep -qE -- "$pattern" <<<"$out"; then
  echo "exit $got as expected but the output lacks /$pattern/:"; echo "$out" | head -c 4000; exit 1
fi
if [[ -n $absent ]] && grep -qE -- "$absent" <<<"$out"; then
  echo "exit $got as expected but the output has /$absent/:"; echo "$out" | head -c 4000; exit 1
fi
if grep -q "internal error" <<<"$out"; then
  echo "exit $got but the message is an internal error:"; echo "$out" | head -c 4000; exit 1
fi
echo "ok: exit $got in ${took}s, output: $(head -c 400 <<<"$out")"
