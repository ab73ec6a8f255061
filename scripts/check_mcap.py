#!/usr/bin/env python3
"""Check an rsts MCAP log with the official Python `mcap` library (an independent reader).

Usage:
  python3 scripts/check_mcap.py FILE.mcap [--rsts-layout] [--samples N]
      [--expect-channels TOPIC[=SCHEMA] ...] [--expect-count TOPIC=N ...] [--optional]

It reads FILE with mcap's indexed reader (summary section, chunk indexes, zstd chunks) and
checks, printing what it found:
  * every message decodes as JSON and its channel has message encoding `json`, schema
    encoding `jsonschema` and a schema whose JSON `title` is the schema name;
  * the per-channel message counts of the summary statistics equal the messages read;
  * `foxglove.FrameTransform` rotations are unit quaternions; with --rsts-layout,
    `foxglove.SceneUpdate` line strips carry at most 2 points (the hodographs of a
    comparison are logged incrementally);
  * the expectations given on the command line:
      --expect-channels /tf=foxglove.FrameTransform /errors   (topic present [with schema])
      --expect-count /tf=2000                                 (exact message count)
      --rsts-layout        the nine channels of docs/mcap.md with their schemas, and a
                           metadata record `rsts` with a software_version
      --samples N          with --rsts-layout: /metadata 1, /tf 2N, every other channel N

Exit status: 0 when all checks pass, 1 when one fails, 2 on bad usage or when the Python
`mcap` package is missing. With --optional a missing package prints
"skipped: python mcap not installed" and exits 0 (for CI machines without it).

Install the reader with:  python3 -m pip install mcap zstandard
(in a virtual environment: python3 -m venv .venv && .venv/bin/pip install mcap zstandard).
"""

import argparse
import json
import math
import sys

RSTS_LAYOUT = {
    "/metadata": "rsts.Metadata",
    "/tf": "foxglove.FrameTransform",
    "/exact/state": "rsts.BodyState",
    "/integrated/state": "rsts.BodyState",
    "/errors": "rsts.Errors",
    "/exact/hodograph/moving": "foxglove.SceneUpdate",
    "/exact/hodograph/fixed": "foxglove.SceneUpdate",
    "/integrated/hodograph/moving": "foxglove.SceneUpdate",
    "/integrated/hodograph/fixed": "foxglove.SceneUpdate",
}


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("file")
    p.add_argument("--expect-channels", nargs="*", default=[], metavar="TOPIC[=SCHEMA]")
    p.add_argument("--expect-count", nargs="*", default=[], metavar="TOPIC=N")
    p.add_argument("--rsts-layout", action="store_true")
    p.add_argument("--samples", type=int)
    p.add_argument("--optional", action="store_true",
                   help="exit 0 with a 'skipped' line when the mcap package is missing")
    return p.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    try:
        from mcap.reader import make_reader
    except ImportError:
        if args.optional:
            print("skipped: python mcap not installed "
                  "(install with: python3 -m pip install mcap zstandard)")
            return 0
        print("error: the Python mcap package is not installed; "
              "install it with: python3 -m pip install mcap zstandard", file=sys.stderr)
        return 2

    failures = []

    def fail(msg):
        failures.append(msg)
        print(f"FAIL: {msg}")

    expected_schema = {}
    expected_count = {}
    for item in args.expect_channels:
        topic, _, schema = item.partition("=")
        expected_schema[topic] = schema or None
    for item in args.expect_count:
        topic, sep, n = item.partition("=")
        if not sep or not n.isdigit():
            print(f"error: --expect-count wants TOPIC=N, got {item!r}", file=sys.stderr)
            return 2
        expected_count[topic] = int(n)
    if args.rsts_layout:
        expected_schema.update(RSTS_LAYOUT)
        if args.samples is not None:
            for topic in RSTS_LAYOUT:
                expected_count.setdefault(topic, args.samples)
            expected_count["/metadata"] = 1
            expected_count["/tf"] = 2 * args.samples

    try:
        f = open(args.file, "rb")
    except OSError as e:
        print(f"error: cannot open {args.file}: {e}", file=sys.stderr)
        return 1
    with f:
        try:
            reader = make_reader(f)
            summary = reader.get_summary()
            counts = {}
            schemas = {}
            encodings = {}
            t_min, t_max = None, None
            for schema, channel, message in reader.iter_messages(log_time_order=False):
                topic = channel.topic
                counts[topic] = counts.get(topic, 0) + 1
                schemas[topic] = schema
                encodings[topic] = channel.message_encoding
                t_min = message.log_time if t_min is None else min(t_min, message.log_time)
                t_max = message.log_time if t_max is None else max(t_max, message.log_time)
                try:
                    data = json.loads(message.data)
                except ValueError as e:
                    fail(f"{topic}: message {message.sequence} is not JSON: {e}")
                    continue
                name = schema.name if schema else None
                if name == "foxglove.FrameTransform":
                    r = data["rotation"]
                    n = math.sqrt(r["x"] ** 2 + r["y"] ** 2 + r["z"] ** 2 + r["w"] ** 2)
                    if abs(n - 1) > 1e-12:
                        fail(f"{topic}: rotation norm {n} at log time {message.log_time}")
                elif name == "foxglove.SceneUpdate" and args.rsts_layout:
                    for e in data["entities"]:
                        for line in e.get("lines", []):
                            if len(line["points"]) > 2:
                                fail(f"{topic}: a line strip with {len(line['points'])} "
                                     "points (hodographs must be incremental)")
            metadata = list(reader.iter_metadata())
        except Exception as e:  # the independent reader rejects the file
            print(f"FAIL: the mcap library cannot read {args.file}: {type(e).__name__}: {e}")
            return 1

    if summary is None or summary.statistics is None:
        fail("no summary section with statistics")
    else:
        stats = summary.statistics
        by_id = {cid: ch.topic for cid, ch in summary.channels.items()}
        for cid, n in stats.channel_message_counts.items():
            topic = by_id.get(cid, f"<channel {cid}>")
            if counts.get(topic, 0) != n:
                fail(f"{topic}: statistics say {n} messages, {counts.get(topic, 0)} read")
        if sum(counts.values()) != stats.message_count:
            fail(f"statistics say {stats.message_count} messages, {sum(counts.values())} read")
        compressions = {ci.compression for ci in summary.chunk_indexes}
        print(f"chunks: {len(summary.chunk_indexes)} ({', '.join(sorted(compressions)) or 'none'})")

    print(f"messages: {sum(counts.values())}, log time {t_min} .. {t_max} ns")
    for topic in sorted(counts):
        s = schemas[topic]
        print(f"  {topic:32} {counts[topic]:8}  {s.name if s else '<no schema>'}"
              f" ({s.encoding if s else '-'}), {encodings[topic]}")
        if encodings[topic] != "json":
            fail(f"{topic}: message encoding {encodings[topic]!r}, expected 'json'")
        if s is None:
            fail(f"{topic}: no schema")
            continue
        if s.encoding != "jsonschema":
            fail(f"{topic}: schema encoding {s.encoding!r}, expected 'jsonschema'")
        try:
            title = json.loads(s.data).get("title")
            if title != s.name:
                fail(f"{topic}: schema title {title!r} differs from its name {s.name!r}")
        except ValueError as e:
            fail(f"{topic}: schema {s.name} is not valid JSON: {e}")

    for topic, schema in expected_schema.items():
        if topic not in counts:
            fail(f"expected channel {topic} has no message")
        elif schema and schemas[topic] is not None and schemas[topic].name != schema:
            fail(f"{topic}: schema {schemas[topic].name}, expected {schema}")
    if args.rsts_layout:
        extra = set(counts) - set(RSTS_LAYOUT)
        if extra:
            fail(f"unexpected channels: {sorted(extra)}")
    for topic, n in expected_count.items():
        if counts.get(topic, 0) != n:
            fail(f"{topic}: {counts.get(topic, 0)} messages, expected {n}")

    for m in metadata:
        print(f"metadata {m.name!r}: software_version={m.metadata.get('software_version')!r}")
    if args.rsts_layout:
        rsts = [m for m in metadata if m.name == "rsts"]
        if len(rsts) != 1:
            fail(f"{len(rsts)} metadata records named 'rsts', expected 1")
        elif not rsts[0].metadata.get("software_version"):
            fail("the 'rsts' metadata record has no software_version")

    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    print("OK: read by the Python mcap library, all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
