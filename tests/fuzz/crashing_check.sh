#!/usr/bin/env bash
# A stand-in for speculum-scene-check that crashes (SIGSEGV) on any scene naming /dev/zero:
# fuzz.self_test runs the fuzzer with it and expects a reported failure, so the harness itself
# is shown able to fail.
for ((i = 2; i <= $#; i += 2)); do
  f=${!i}
  if grep -q "dev/zero" "$f" 2>/dev/null; then kill -SEGV $$; fi
  echo "$f: fine"; echo "@@ exit 0"
done
