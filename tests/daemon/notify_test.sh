#!/usr/bin/env bash
# `systemctl status` tells the truth (issue 15): under systemd (NOTIFY_SOCKET) the daemon sends
# READY=1, then with every status message STATUS= with the cameras in use / configured, the
# frame rate, the tracks and the health in words, and STOPPING=1 with STATUS=draining at the
# end. A Python datagram socket stands in for systemd's notify socket.
source "$(dirname "$0")/common.sh"
write_config "$OUT/daemon.yaml"
SOCK=$OUT/notify.sock
python3 - "$SOCK" "$OUT/notify.txt" << 'EOF_PY' &
import socket, sys, time
s = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
s.bind(sys.argv[1])
s.settimeout(0.2)
end = time.time() + 30
with open(sys.argv[2], "w") as out:
    while time.time() < end:
        try:
            msg = s.recv(4096).decode()
        except socket.timeout:
            continue
        out.write(msg.replace("\n", " | ") + "\n")
        out.flush()
        if "STOPPING=1" in msg:
            break
EOF_PY
LISTENER=$!
for _ in $(seq 50); do [ -S "$SOCK" ] && break; sleep 0.1; done
NOTIFY_SOCKET=$SOCK expect_exit 0 "$OUT/daemon.log" "$MVTRACKD" --config "$OUT/daemon.yaml" \
  --input-log "$P/detections.lcmlog" --input-speed 2
wait $LISTENER || true
expect_grep "^READY=1" "$OUT/notify.txt"
expect_grep "^STATUS=tracking: 3/3 cameras, [0-9]+\.[0-9] fps, [0-9]+ tracks \([0-9]+ confirmed\), OK$" \
  "$OUT/notify.txt"
expect_grep "^STOPPING=1 \| STATUS=draining$" "$OUT/notify.txt"
# Nothing replaces "draining" afterwards (the final status is published while stopping).
[ "$(tail -1 "$OUT/notify.txt")" = "STOPPING=1 | STATUS=draining" ] ||
  fail "the last notification is not the draining one: $(tail -1 "$OUT/notify.txt")"
echo "ok"
