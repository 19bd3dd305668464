#!/usr/bin/env python3
"""Decodes an LCM log with the generated mvtrack Python types and prints the canonical dump.

The dump format is described in tests/lcmtypes/sample_messages.h. Each event is decoded by its
fingerprint, must re-encode to the same bytes, and with --expected the whole output must equal
the C++ side's dump.

The generated Python types need only the standard library (struct), so this runs without the
`lcm` Python module: the log is read with the small reader below, which implements LCM's
documented log format (per event: sync word 0xEDA1DA01, int64 event number, int64 timestamp,
int32 channel length, int32 data length, channel, data; all big-endian).

Usage: decode_log.py --types-dir <build>/lcmtypes/python [--expected DUMP_FILE] LOG
Exit status: 0 on success, 1 on a decode, re-encode or comparison failure, 2 on bad usage.
"""

import argparse
import difflib
import importlib
import struct
import sys

LOG_SYNC_WORD = 0xEDA1DA01
EVENT_HEADER = struct.Struct(">IqqII")


def read_events(path):
    """Yields (event_number, timestamp_us, channel, data) for every event of an LCM log."""
    with open(path, "rb") as log:
        while True:
            header = log.read(EVENT_HEADER.size)
            if not header:
                return
            if len(header) < EVENT_HEADER.size:
                raise ValueError("truncated event header at offset %d" % (log.tell() - len(header)))
            sync, number, timestamp, channel_len, data_len = EVENT_HEADER.unpack(header)
            if sync != LOG_SYNC_WORD:
                raise ValueError("bad sync word 0x%08x before event %d" % (sync, number))
            channel = log.read(channel_len)
            data = log.read(data_len)
            if len(channel) != channel_len or len(data) != data_len:
                raise ValueError("truncated event %d" % number)
            yield number, timestamp, channel.decode("ascii"), data


def lcm_types(package):
    """Maps packed fingerprint -> generated class for every type in `package`."""
    types = {}
    for name in dir(package):
        cls = getattr(package, name)
        if isinstance(cls, type) and hasattr(cls, "_get_packed_fingerprint"):
            types[cls._get_packed_fingerprint()] = cls
    return types


def is_message(value):
    return hasattr(type(value), "_get_packed_fingerprint")


def real_text(value):
    return "0x%016x" % struct.unpack(">Q", struct.pack(">d", value))[0]


def string_text(value):
    out = ['"']
    for byte in value.encode("utf-8"):
        if byte < 0x20 or byte > 0x7E or byte in (ord('"'), ord("\\")):
            out.append("\\x%02x" % byte)
        else:
            out.append(chr(byte))
    out.append('"')
    return "".join(out)


def dump_value(value, path, out):
    if is_message(value):
        dump(value, path + ".", out)
    elif isinstance(value, bool):  # before int: bool is an int subclass
        out.append("%s=%s\n" % (path, "true" if value else "false"))
    elif isinstance(value, int):
        out.append("%s=%d\n" % (path, value))
    elif isinstance(value, float):
        out.append("%s=%s\n" % (path, real_text(value)))
    elif isinstance(value, str):
        out.append("%s=%s\n" % (path, string_text(value)))
    else:
        raise TypeError("unsupported field type at %s: %r" % (path, value))


def dump(msg, prefix, out):
    for name in sorted(type(msg).__slots__):
        value = getattr(msg, name)
        if isinstance(value, (list, tuple)):
            for i, element in enumerate(value):
                dump_value(element, "%s%s[%d]" % (prefix, name, i), out)
        else:
            dump_value(value, prefix + name, out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--types-dir", required=True,
                        help="directory holding the generated package mvtrack/")
    parser.add_argument("--expected", help="dump the output must equal")
    parser.add_argument("log", help="LCM log file")
    args = parser.parse_args()

    sys.path.insert(0, args.types_dir)
    package = importlib.import_module("mvtrack")
    types = lcm_types(package)

    ok = True
    out = []
    for index, (_, _, channel, data) in enumerate(read_events(args.log)):
        cls = types.get(data[:8])
        if cls is None:
            print("event %d on %s: unknown fingerprint %s" % (index, channel, data[:8].hex()),
                  file=sys.stderr)
            ok = False
            continue
        msg = cls.decode(data)
        if msg.encode() != data:
            print("event %d on %s: %s re-encodes to different bytes" % (index, channel,
                                                                         cls.__name__),
                  file=sys.stderr)
            ok = False
        out.append("event %d channel=%s type=%s\n" % (index, channel, cls.__name__))
        dump(msg, "", out)
    text = "".join(out)
    sys.stdout.write(text)

    if args.expected:
        with open(args.expected, encoding="utf-8") as f:
            expected = f.read()
        if expected != text:
            diff = difflib.unified_diff(expected.splitlines(True), text.splitlines(True),
                                        "C++ dump", "Python dump", n=1)
            sys.stderr.writelines(list(diff)[:40])
            ok = False
        else:
            print("decode_log.py: output matches %s" % args.expected, file=sys.stderr)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
