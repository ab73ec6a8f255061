#!/usr/bin/env node
// Read MCAP files with @mcap/core as Foxglove Studio 1.x ships it (2.1.0) and with today's
// @mcap/core, through the indexed reader (what Studio uses for a file with a summary) and the
// stream reader, and validate every JSON message with Ajv against the schema its channel
// carries and, for foxglove.* schemas, against the official @foxglove/schemas JSON schema.
//
//   node read_mcap.cjs FILE...          (packages from NODE_PATH: scripts/node_deps.sh mcap-readers)
//   node read_mcap.cjs --print-schema foxglove.SceneUpdate
//
// Prints one JSON document: {"readers": {...versions}, "files": [{file, readers: {name:
// {ok, error?, indexed: {messages, by_topic, metadata}, stream: {messages, by_topic}}},
// schemas: {name: {channels, official, equals_official, invalid_messages, first_error}}}]}.
// Exit 0 when every reader read every file, the counts agree with the file's statistics,
// every message is valid and every foxglove.* schema equals the official one; 1 otherwise;
// 2 on bad usage or missing packages.
"use strict";
const fs = require("fs");
const path = require("path");

function need(name) {
  try {
    return require(name);
  } catch (e) {
    console.error(`read_mcap: cannot load ${name} (run scripts/node_deps.sh mcap-readers and set NODE_PATH): ${e.message}`);
    process.exit(2);
  }
}

const READERS = { "@mcap/core 2.1.0": "mcap-core-2.1.0", "@mcap/core current": "mcap-core-current" };
const fzstd = need("fzstd");
const Ajv = need("ajv");
const official = need("@foxglove/schemas/jsonschema");
const decompressHandlers = {
  zstd: (buffer, size) => fzstd.decompress(buffer, new Uint8Array(Number(size))),
};

// The version of an installed package (its package.json is not always exported).
function version(pkg) {
  let dir = path.dirname(require.resolve(pkg));
  while (!fs.existsSync(path.join(dir, "package.json")) || path.basename(path.dirname(dir)) === "dist") {
    const up = path.dirname(dir);
    if (up === dir) return "unknown";
    dir = up;
  }
  for (; dir !== path.dirname(dir); dir = path.dirname(dir)) {
    const p = JSON.parse(fs.readFileSync(path.join(dir, "package.json"), "utf8"));
    if (p.version) return p.version;
  }
  return "unknown";
}

function officialSchema(name) {
  return name.startsWith("foxglove.") ? official[name.slice("foxglove.".length)] : undefined;
}

// Deep equality of JSON values (key order ignored).
function equal(a, b) {
  if (a === b) return true;
  if (typeof a !== "object" || typeof b !== "object" || a === null || b === null) return false;
  if (Array.isArray(a) !== Array.isArray(b)) return false;
  const ka = Object.keys(a), kb = Object.keys(b);
  return ka.length === kb.length && ka.every((k) => Object.prototype.hasOwnProperty.call(b, k) && equal(a[k], b[k]));
}

function count(map, key) {
  map[key] = (map[key] || 0) + 1;
}

async function readIndexed(core, bytes) {
  const readable = {
    size: async () => BigInt(bytes.length),
    read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
  };
  const reader = await core.McapIndexedReader.Initialize({ readable, decompressHandlers });
  const byTopic = {};
  let messages = 0;
  const decoded = [];
  for await (const m of reader.readMessages({ validateCrcs: true })) {
    const ch = reader.channelsById.get(m.channelId);
    count(byTopic, ch.topic);
    messages++;
    decoded.push([ch, m.data]);
  }
  const metadata = [];
  for await (const md of reader.readMetadata()) metadata.push(md.name);
  const stats = reader.statistics;
  if (!stats) throw new Error("no statistics record in the summary");
  if (BigInt(messages) !== stats.messageCount) {
    throw new Error(`indexed read gave ${messages} messages, the statistics say ${stats.messageCount}`);
  }
  return { result: { messages, by_topic: byTopic, metadata, chunks: reader.chunkIndexes.length }, decoded, reader };
}

function readStream(core, bytes) {
  const reader = new core.McapStreamReader({ decompressHandlers, validateCrcs: true });
  reader.append(bytes);
  const channels = new Map();
  const byTopic = {};
  let messages = 0;
  for (let rec; (rec = reader.nextRecord()); ) {
    if (rec.type === "Channel") channels.set(rec.id, rec);
    if (rec.type === "Message") {
      count(byTopic, channels.get(rec.channelId).topic);
      messages++;
    }
  }
  if (!reader.done()) throw new Error(`stream reader stopped with ${reader.bytesRemaining()} bytes left`);
  return { messages, by_topic: byTopic };
}

function validate(reader, decoded) {
  const ajv = new Ajv({ strict: false, allErrors: false });
  const schemas = {};
  const validators = new Map();
  for (const [id, s] of reader.schemasById) {
    if (s.encoding !== "jsonschema") continue;
    const carried = JSON.parse(new TextDecoder().decode(s.data));
    const off = officialSchema(s.name);
    schemas[s.name] = { official: off !== undefined, equals_official: off === undefined ? null : equal(carried, off), channels: 0, messages: 0, invalid_messages: 0 };
    validators.set(id, [ajv.compile(carried), off && ajv.compile(off)]);
  }
  for (const [ch, data] of decoded) {
    const schema = reader.schemasById.get(ch.schemaId);
    const entry = schemas[schema.name];
    entry.messages++;
    let msg;
    try {
      msg = JSON.parse(new TextDecoder().decode(data));
    } catch (e) {
      entry.invalid_messages++;
      entry.first_error = entry.first_error || `${ch.topic}: not JSON: ${e.message}`;
      continue;
    }
    for (const [which, v] of [["carried", validators.get(ch.schemaId)[0]], ["official", validators.get(ch.schemaId)[1]]]) {
      if (v && !v(msg)) {
        entry.invalid_messages++;
        entry.first_error = entry.first_error || `${ch.topic} (${which} schema): ${ajv.errorsText(v.errors)}`;
        break;
      }
    }
  }
  for (const ch of reader.channelsById.values()) {
    const s = reader.schemasById.get(ch.schemaId);
    if (s && schemas[s.name]) schemas[s.name].channels++;
  }
  return schemas;
}

async function main(argv) {
  if (argv[0] === "--print-schema" && argv.length === 2) {
    const s = officialSchema(argv[1]);
    if (!s) {
      console.error(`read_mcap: no official schema named ${argv[1]}`);
      return 2;
    }
    process.stdout.write(JSON.stringify(s, null, 2) + "\n");
    return 0;
  }
  if (argv.length === 0 || argv[0].startsWith("-")) {
    console.error("usage: node read_mcap.cjs FILE... | --print-schema foxglove.NAME");
    return 2;
  }
  const cores = Object.entries(READERS).map(([label, pkg]) => [label, need(pkg), version(pkg)]);
  const doc = { readers: Object.fromEntries(cores.map(([l, , v]) => [l, v])), schemas_package: version("@foxglove/schemas"), files: [] };
  let ok = true;
  for (const file of argv) {
    const bytes = new Uint8Array(fs.readFileSync(file));
    const entry = { file, readers: {} };
    for (const [label, core] of cores) {
      const r = { ok: true };
      try {
        const { result, decoded, reader } = await readIndexed(core, bytes);
        r.indexed = result;
        r.stream = readStream(core, bytes);
        if (r.stream.messages !== result.messages) {
          throw new Error(`stream read gave ${r.stream.messages} messages, indexed read ${result.messages}`);
        }
        if (!entry.schemas) {
          entry.schemas = validate(reader, decoded);
          for (const s of Object.values(entry.schemas)) {
            if (s.invalid_messages > 0 || s.equals_official === false) ok = false;
          }
        }
      } catch (e) {
        r.ok = false;
        r.error = String(e && e.message ? e.message : e);
        ok = false;
      }
      entry.readers[label] = r;
    }
    doc.files.push(entry);
  }
  process.stdout.write(JSON.stringify(doc, null, 2) + "\n");
  return ok ? 0 : 1;
}

main(process.argv.slice(2)).then(
  (code) => process.exit(code),
  (e) => {
    console.error(`read_mcap: ${e.stack || e}`);
    process.exit(2);
  },
);
