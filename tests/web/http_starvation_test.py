#!/usr/bin/env python3
"""mvtrack web's HTTP surface under attack (issue 39): /healthz and /metrics stay reachable.

Starts `mvtrack web` on 127.0.0.1 (any free port; LCM memq://, so nothing leaves the process)
and, for SECONDS, keeps up at once
  - 50 slow senders: each sends a request's headers at one byte per second, never ending them,
    and reconnects as soon as the server closes the connection;
  - 200 /events clients: each requests /events, reads what it gets, reconnects when closed;
  - a flood of large requests: 200 MB announced POST bodies, a request of a million header
    lines, a 1 MB request line, sent as fast as the server takes them;
while a prober asks /healthz and /metrics every 50 ms, one request at a time. Checked: every
probe answered (none failed, none over 5 s), p99 < 1 s; the server's peak RSS (VmHWM) < 64 MB;
a request with 120 header lines of 9.4 KiB in total is refused (civetweb says 400) and one of 65 short headers
is answered; the server is alive afterwards and stops cleanly on SIGTERM.
With cpp-httplib 0.11 (before issue 39) the prober got no answer while the slow senders held
the pool's 12 threads, and a million header lines took the process to 261 MB.

Usage: http_starvation_test.py MVTRACK OUT_DIR [SECONDS]   (writes OUT_DIR/result.json)
"""
import asyncio
import json
import multiprocessing
import os
import re
import signal
import subprocess
import sys
import time

SLOW_SENDERS = 50
EVENTS_CLIENTS = 200
PROBE_TIMEOUT_S = 5.0
P99_LIMIT_S = 1.0
RSS_LIMIT_KB = 64 * 1024
RSS_AT_REST_KB = 12 * 1024  # mvtrack web at rest, release build


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


async def request(port, data, timeout):
    """Sends `data`, reads the whole response; returns (status, seconds) or (None, seconds)."""
    start = time.monotonic()
    try:
        reader, writer = await asyncio.wait_for(
            asyncio.open_connection("127.0.0.1", port), timeout)
        writer.write(data)
        await writer.drain()
        response = await asyncio.wait_for(reader.read(), timeout - (time.monotonic() - start))
        writer.close()
    except (OSError, asyncio.TimeoutError):
        return None, time.monotonic() - start
    match = re.match(rb"HTTP/1\.[01] (\d{3})", response)
    return (int(match.group(1)) if match else None), time.monotonic() - start


async def slow_sender(port, stop, counts):
    while not stop.is_set():
        try:
            reader, writer = await asyncio.open_connection("127.0.0.1", port)
            writer.write(b"GET /healthz HTTP/1.1\r\nHost: x\r\nX-Slow: ")
            await writer.drain()
            counts["slow_connections"] += 1
            while not stop.is_set():
                writer.write(b"x")  # a byte a second, the headers never end
                await writer.drain()
                try:
                    if not await asyncio.wait_for(reader.read(4096), 1.0):
                        break  # the server closed the connection
                    break  # it answered (408/400) and will close
                except asyncio.TimeoutError:
                    pass
            writer.close()
        except OSError:
            await asyncio.sleep(0.05)


async def events_client(port, stop, counts):
    while not stop.is_set():
        try:
            reader, writer = await asyncio.open_connection("127.0.0.1", port)
            writer.write(b"GET /events HTTP/1.1\r\nHost: x\r\n\r\n")
            await writer.drain()
            counts["events_requests"] += 1
            while not stop.is_set():
                try:
                    if not await asyncio.wait_for(reader.read(65536), 0.5):
                        break
                except asyncio.TimeoutError:
                    pass
            writer.close()
        except OSError:
            pass
        await asyncio.sleep(0.2)  # refused (503): try again soon


async def flood(port, stop, kind, counts):
    chunk = b"a" * 65536
    while not stop.is_set():
        try:
            reader, writer = await asyncio.open_connection("127.0.0.1", port)
            if kind == "body":
                writer.write(b"POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 200000000\r\n\r\n")
                for _ in range(3200):  # 200 MB
                    writer.write(chunk)
                    await writer.drain()
            elif kind == "headers":
                writer.write(b"GET / HTTP/1.1\r\nHost: x\r\n")
                lines = b"h: v\r\n" * 10000
                for _ in range(100):  # a million header lines
                    writer.write(lines)
                    await writer.drain()
            else:
                writer.write(b"GET /" + b"u" * (1 << 20) + b" HTTP/1.1\r\nHost: x\r\n\r\n")
                await writer.drain()
            await asyncio.wait_for(reader.read(), 5.0)
            writer.close()
        except (OSError, asyncio.TimeoutError):
            pass  # refused and closed by the server: what it should do
        counts["flood_" + kind] += 1
        await asyncio.sleep(0.01)


def probe(port, seconds):
    """/healthz and /metrics in turn every 50 ms, one at a time: [(path, status, seconds)]."""
    samples = []
    end = time.monotonic() + seconds
    i = 0
    while time.monotonic() < end:
        path = [b"/healthz", b"/metrics"][i % 2]
        i += 1
        status, elapsed = asyncio.run(request(
            port, b"GET " + path + b" HTTP/1.1\r\nHost: x\r\n\r\n", PROBE_TIMEOUT_S))
        samples.append((path.decode(), status, elapsed))
        time.sleep(0.05)
    return samples


async def attack(port, seconds):
    stop = asyncio.Event()
    counts = {"slow_connections": 0, "events_requests": 0, "flood_body": 0, "flood_headers": 0,
              "flood_line": 0}
    tasks = [asyncio.create_task(slow_sender(port, stop, counts)) for _ in range(SLOW_SENDERS)]
    tasks += [asyncio.create_task(events_client(port, stop, counts))
              for _ in range(EVENTS_CLIENTS)]
    tasks += [asyncio.create_task(flood(port, stop, kind, counts))
              for kind in ("body", "headers", "line") for _ in range(2)]
    await asyncio.sleep(seconds)
    stop.set()
    await asyncio.wait(tasks, timeout=10)
    return counts


def attacker(port, seconds, out):
    """The attack, in its own process (the prober must not wait for its event loop)."""
    counts = asyncio.run(attack(port, seconds))
    with open(os.path.join(out, "attack.json"), "w") as f:
        json.dump(counts, f)


async def header_limits(port):
    many = b"".join(b"x-h%03d: %s\r\n" % (i, b"v" * 70) for i in range(120))  # 9.4 KiB
    too_many, _ = await request(port, b"GET /healthz HTTP/1.1\r\nHost: x\r\n" + many + b"\r\n", 5)
    some = b"".join(b"x-h%02d: v\r\n" % i for i in range(65))
    fine, _ = await request(port, b"GET /healthz HTTP/1.1\r\nHost: x\r\n" + some + b"\r\n", 5)
    return too_many, fine


def vm_hwm_kb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1])
    return -1


def main():
    if len(sys.argv) not in (3, 4):
        print(__doc__)
        sys.exit(2)
    mvtrack, out = sys.argv[1], sys.argv[2]
    seconds = float(sys.argv[3]) if len(sys.argv) == 4 else 10.0
    os.makedirs(out, exist_ok=True)
    log = open(os.path.join(out, "web.log"), "w")
    web = subprocess.Popen([mvtrack, "web", "--listen", "127.0.0.1:0", "--url", "memq://"],
                           stderr=log, stdout=log)
    try:
        port = None
        for _ in range(100):
            with open(os.path.join(out, "web.log")) as f:
                m = re.search(r"serving http://127\.0\.0\.1:(\d+)/", f.read())
            if m:
                port = int(m.group(1))
                break
            time.sleep(0.1)
        if port is None:
            fail("mvtrack web did not start (see web.log)")
        rss_start = vm_hwm_kb(web.pid)
        with open(f"/proc/{web.pid}/maps") as f:
            maps = f.read()
            sanitized = "libasan" in maps or "libtsan" in maps
        attack_process = multiprocessing.Process(target=attacker, args=(port, seconds + 2, out))
        attack_process.start()
        time.sleep(2.0)  # let the attack take hold before measuring
        samples = probe(port, seconds)
        attack_process.join(30)
        with open(os.path.join(out, "attack.json")) as f:
            counts = json.load(f)
        too_many, fine = asyncio.run(header_limits(port))
        after, _ = asyncio.run(request(port, b"GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n", 5))
        rss_peak = vm_hwm_kb(web.pid)
    finally:
        web.send_signal(signal.SIGTERM)
        try:
            code = web.wait(timeout=10)
        except subprocess.TimeoutExpired:
            web.kill()
            code = "hung"
    latencies = sorted(s for _, _, s in samples)
    failed = [(p, st, round(s, 3)) for p, st, s in samples if st is None]
    p99 = latencies[min(len(latencies) - 1, int(0.99 * len(latencies)))] if latencies else None
    result = {"probes": len(samples), "failed": len(failed), "p50_s": latencies[len(latencies) // 2]
              if latencies else None, "p99_s": p99, "max_s": latencies[-1] if latencies else None,
              "rss_start_kb": rss_start, "rss_peak_kb": rss_peak, "sanitizer": sanitized, "too_many_headers": too_many,
              "65_headers": fine, "after": after, "exit": code, **counts}
    with open(os.path.join(out, "result.json"), "w") as f:
        json.dump(result, f, indent=1)
    print(json.dumps(result))
    if len(samples) < 50:
        fail(f"only {len(samples)} probes in {seconds} s")
    if failed:
        fail(f"{len(failed)} probes got no answer within {PROBE_TIMEOUT_S} s: {failed[:5]}")
    if p99 >= P99_LIMIT_S:
        fail(f"/healthz and /metrics p99 {p99:.3f} s >= {P99_LIMIT_S} s")
    if counts["slow_connections"] < SLOW_SENDERS or counts["events_requests"] < EVENTS_CLIENTS:
        fail(f"the attack did not take hold: {counts}")
    # Under AddressSanitizer or ThreadSanitizer (the asan and tsan presets) the shadow memory alone
    # is over the limit: there the growth during the attack is what is bounded.
    if sanitized and rss_peak - rss_start >= RSS_LIMIT_KB - RSS_AT_REST_KB:
        fail(f"peak RSS grew by {rss_peak - rss_start} kB under the attack (sanitizer build)")
    if not sanitized and rss_peak >= RSS_LIMIT_KB:
        fail(f"peak RSS {rss_peak} kB >= {RSS_LIMIT_KB} kB")
    if too_many not in (400, 413, 431):
        fail(f"9.4 KiB of headers: got {too_many}, expected a refusal (400, 413 or 431)")
    if fine != 503:  # /healthz without a status: 503 UNKNOWN, i.e. answered
        fail(f"65 short headers: got {fine}, expected the /healthz answer 503")
    if after != 503:
        fail(f"after the attack: got {after}, expected the /healthz answer 503")
    if code != 0:
        fail(f"mvtrack web exited with {code} on SIGTERM")
    print("ok")


if __name__ == "__main__":
    main()
