#!/usr/bin/env bash
# Decodes the C++-written sample log in Java with exactly the class path lcm-spy gets from the
# launcher (plus DecodeLog's own class directory), and compares with the C++ dump.
# Usage: run_java_decode.sh <java> <launcher> <DecodeLog class dir> <log> <expected dump>
set -euo pipefail
java=$1 launcher=$2 classes=$3 log=$4 expected=$5
classpath=$("$launcher" --print-classpath)
# Short-lived JVM: the C1-only JIT roughly halves start-up time.
exec "$java" -XX:TieredStopAtLevel=1 -cp "$classpath:$classes" \
  DecodeLog --expected "$expected" "$log" >/dev/null
