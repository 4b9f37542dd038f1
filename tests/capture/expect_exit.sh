#!/usr/bin/env bash
# expect_exit.sh CODE PATTERN CMD...: passes when CMD exits with CODE and its stderr+stdout
# contains PATTERN (grep -E). Used for the command-line contract of docs/design.md section 6 (command lines).
code=$1; pattern=$2; shift 2
out=$("$@" 2>&1); got=$?
if [[ $got -ne $code ]]; then
  echo "expected exit $code, got $got from: $*"; echo "$out"; exit 1
fi
if ! grep -qE -- "$pattern" <<<"$out"; then
  echo "exit $got as expected but the output lacks /$pattern/:"; echo "$out"; exit 1
fi
echo "ok: exit $got, output: $(head -c 300 <<<"$out")"
