#!/usr/bin/env bash
# A source you can recognise (issue 39), live in a private network namespace (never on the
# machine's network): a real mvtrackd publishes its status over udpm://, `mvtrack web` and
# `mvtrack status` watch it, and publish_status plays a second daemon or a forger.
#   - the daemon alone: OK, and `mvtrack status` names its 16-hex-digit instance;
#   - a second instance publishing at the same time: /healthz 503 and `mvtrack status` exit 2,
#     both saying "two tracker instances";
#   - a status with the daemon's own instance id and an old sequence (a replay): "went
#     backwards", CRITICAL;
#   - once everything was quiet, a new instance: "restarted", a WARNING (200).
# Skipped (exit 77, with a message) where no namespace can be created.
source "$(dirname "$0")/common.sh"
PUBLISH_STATUS=${5:-}
[ -x "$PUBLISH_STATUS" ] || fail "the status publisher is missing ($PUBLISH_STATUS)"
require_netns
command -v curl > /dev/null || { echo "SKIP: curl is not installed"; exit 77; }
URL="udpm://239.255.76.67:7667?ttl=0"
write_config "$OUT/daemon.yaml"
export MVTRACKD MVTRACK OUT P URL PUBLISH_STATUS
unshare -n bash -euc '
  ip link set lo up
  ip route add 224.0.0.0/4 dev lo
  health() {  # health NAME: /healthz code and text into NAME.code and NAME.txt
    curl -s -o "$OUT/$1.txt" -w "%{http_code}\n" http://127.0.0.1:18081/healthz > "$OUT/$1.code"
  }
  status() {  # status NAME: mvtrack status output and exit code into status_NAME.txt / .code
    set +e
    "$MVTRACK" status --url "$URL" --timeout 3 > "$OUT/status_$1.txt"
    echo $? > "$OUT/status_$1.code"
    set -e
  }
  "$MVTRACK" web --listen 127.0.0.1:18081 --url "$URL" --stale-after 2 > "$OUT/web.log" 2>&1 &
  WEB=$!
  for _ in $(seq 100); do grep -q "serving http" "$OUT/web.log" && break; sleep 0.1; done
  "$MVTRACKD" --config "$OUT/daemon.yaml" --input-log "$P/detections.lcmlog" \
    --input-speed 0.5 --output-url "$URL" > "$OUT/daemon.log" 2>&1 &
  DAEMON=$!
  sleep 1.5
  health alone
  status alone
  instance=$(sed -n "s/.*, instance \([0-9a-f]*\), status #.*/\1/p" "$OUT/status_alone.txt")
  echo "$instance" > "$OUT/instance.txt"
  # A second instance, five statuses a second for 3 s.
  "$PUBLISH_STATUS" "$URL" MVTRACK_STATUS 00000000f0f0f0f0 0 15 200 &
  SECOND=$!
  sleep 0.7
  health two
  status two
  wait $SECOND
  sleep 2.5  # longer than --stale-after: the conflict is forgotten
  # A replay: the daemon'"'"'s own instance id with sequence 1.
  "$PUBLISH_STATUS" "$URL" MVTRACK_STATUS "${instance:-none}" 1 1 1
  sleep 0.2
  health backwards
  wait $DAEMON
  sleep 2.5
  # After everything was quiet: a new instance, as a restarted daemon.
  "$PUBLISH_STATUS" "$URL" MVTRACK_STATUS 0123456789abcdef 0 5 200
  health restarted
  kill -TERM $WEB
  wait $WEB
' || fail "the namespace run failed (see $OUT/*.log)"
instance=$(cat "$OUT/instance.txt")
[[ "$instance" =~ ^[0-9a-f]{16}$ ]] ||
  fail "mvtrack status names no 16-hex-digit instance: $(head -2 "$OUT/status_alone.txt")"
expect_eq "$(cat "$OUT/alone.code")" 200 "/healthz with the daemon alone"
expect_eq "$(cat "$OUT/status_alone.code")" 0 "mvtrack status with the daemon alone"
expect_eq "$(cat "$OUT/two.code")" 503 "/healthz with two instances"
expect_grep "^CRITICAL: two tracker instances publish statuses on this channel" "$OUT/two.txt"
expect_eq "$(cat "$OUT/status_two.code")" 2 "mvtrack status with two instances"
expect_grep "^mvtrack status: CRITICAL: two tracker instances publish" "$OUT/status_two.txt"
expect_eq "$(cat "$OUT/backwards.code")" 503 "/healthz after a replayed status"
expect_grep "the status sequence of instance $instance went backwards \(1 after [0-9]+\)" \
  "$OUT/backwards.txt"
expect_eq "$(cat "$OUT/restarted.code")" 200 "/healthz after a restart"
expect_grep "^WARNING: the tracker restarted: instance 0123456789abcdef replaced " \
  "$OUT/restarted.txt"
echo "ok"
