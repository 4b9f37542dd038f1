#!/usr/bin/env bash
# read_only_out_test.sh EXPECT CAPTURE SCENE DIR: --out under a folder nobody may write is exit 2
# before any device starts. Root writes anywhere, so as root the tool runs as 'nobody'
# (setpriv); everything it reads must then be world-readable, which the checkout is.
set -u
expect=$1; capture=$2; scene=$3; dir=$4
rm -rf "$dir"; mkdir -p "$dir/locked"; chmod 555 "$dir/locked"; chmod 755 "$dir"
run=()
if [[ $(id -u) -eq 0 ]]; then run=(setpriv --reuid=65534 --regid=65534 --clear-groups); fi
"$expect" 2 "--out $dir/locked/sub: cannot create the folder: Permission denied" "" "${run[@]}" "$capture" --scene "$scene" --out "$dir/locked/sub"
rc=$?
"$expect" 2 "--out $dir/locked: the folder is not writable" "" "${run[@]}" "$capture" --scene "$scene" --out "$dir/locked" || rc=1
exit $rc
