#!/usr/bin/env node
// Reads an MCAP file with the ecosystem's own readers (viewer/node_modules, pinned by
// viewer/package-lock.json): @mcap/core's McapIndexedReader, which seeks through the summary,
// and its McapStreamReader (CRCs validated) over the whole file; both must give the same
// messages. Messages on `cdr` channels with a `ros2msg` schema are decoded with
// @foxglove/rosmsg's parser and @foxglove/rosmsg2-serialization's MessageReader.
//
//   node tests/recordings/read_mcap.mjs FILE.mcap
//
// Prints one JSON line per message in log-time order (ties: channel id, then sequence):
//   {"topic", "schema", "log_time", "publish_time" (nanoseconds as decimal strings),
//    "sequence", "message"}
// where in "message" BigInts are decimal strings, Uint8Array and Int8Array are
// {"length", "sha256"}, other typed arrays plain arrays, and non-finite numbers "inf", "-inf",
// "nan". A message that is not decoded has "message": null and "data": {"length", "sha256"}.
// Then one line {"summary": {"messages", "channels": {topic: count}, "metadata": {name: {k: v}},
// "attachments": [names], "profile", "library"}}.
// The data section's and the summary's CRCs (when not 0) are checked too. Exit 0, or 1 with one
// message on any error.

import { createHash } from "node:crypto";
import fs from "node:fs";
import { createRequire } from "node:module";
import path from "node:path";
import { fileURLToPath } from "node:url";

const HERE = path.dirname(fileURLToPath(import.meta.url));
const VIEWER = path.join(HERE, "..", "..", "viewer");
const require = createRequire(path.join(VIEWER, "package.json"));

function fail(message) {
  process.stderr.write(`read_mcap: ${message}\n`);
  process.exit(1);
}

// A readable over a FileHandle for McapIndexedReader: reads exactly what is asked, or fails.
class FileHandleReadable {
  constructor(handle, size) {
    this.handle = handle;
    this.fileSize = size;
  }
  async size() {
    return this.fileSize;
  }
  async read(offset, length) {
    if (offset < 0n || length < 0n || offset + length > this.fileSize) {
      throw new Error(`read of ${length} bytes at ${offset} is past the file's end (${this.fileSize})`);
    }
    const buffer = new Uint8Array(Number(length));
    let done = 0;
    while (done < buffer.length) {
      const { bytesRead } = await this.handle.read(buffer, done, buffer.length - done, Number(offset) + done);
      if (bytesRead === 0) throw new Error(`the file ended while reading at ${offset}`);
      done += bytesRead;
    }
    return buffer;
  }
}

// CRC-32 as zlib computes it (the MCAP spec's), over ranges of a file read in pieces.
const CRC_TABLE = (() => {
  const table = new Uint32Array(256);
  for (let i = 0; i < 256; i++) {
    let c = i;
    for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
    table[i] = c >>> 0;
  }
  return table;
})();
class RangeCrc {
  constructor(start, end) {
    this.start = start;
    this.end = end;
    this.state = 0xffffffff;
  }
  update(piece, pieceStart) {
    const from = Math.max(this.start, pieceStart);
    const to = Math.min(this.end, pieceStart + piece.length);
    let c = this.state;
    for (let i = from; i < to; i++) c = CRC_TABLE[(c ^ piece[i - pieceStart]) & 0xff] ^ (c >>> 8);
    this.state = c;
  }
  value() {
    return (this.state ^ 0xffffffff) >>> 0;
  }
}

function sha256(bytes) {
  return createHash("sha256").update(bytes).digest("hex");
}

// The decoded message as JSON can carry it.
function toJson(value) {
  if (typeof value === "bigint") return value.toString();
  if (typeof value === "number") {
    if (Number.isNaN(value)) return "nan";
    if (value === Infinity) return "inf";
    if (value === -Infinity) return "-inf";
    return value;
  }
  if (value instanceof Uint8Array || value instanceof Int8Array) {
    return { length: value.length, sha256: sha256(new Uint8Array(value.buffer, value.byteOffset, value.byteLength)) };
  }
  if (ArrayBuffer.isView(value)) return Array.from(value, toJson);
  if (Array.isArray(value)) return value.map(toJson);
  if (value !== null && typeof value === "object") {
    const out = {};
    for (const [key, field] of Object.entries(value)) out[key] = toJson(field);
    return out;
  }
  return value;
}

function compareMessages(a, b) {
  if (a.logTime !== b.logTime) return a.logTime < b.logTime ? -1 : 1;
  if (a.channelId !== b.channelId) return a.channelId - b.channelId;
  return a.sequence - b.sequence;
}

function sameBytes(a, b) {
  return a.length === b.length && Buffer.compare(Buffer.from(a.buffer, a.byteOffset, a.length), Buffer.from(b.buffer, b.byteOffset, b.length)) === 0;
}

async function readIndexed(file, decompressHandlers, McapIndexedReader) {
  const handle = await fs.promises.open(file, "r");
  try {
    const { size } = await handle.stat();
    const reader = await McapIndexedReader.Initialize({ readable: new FileHandleReadable(handle, BigInt(size)), decompressHandlers });
    const messages = [];
    for await (const m of reader.readMessages({ validateCrcs: true })) messages.push(m);
    const metadata = [];
    for await (const m of reader.readMetadata()) metadata.push(m);
    const attachments = [];
    for await (const a of reader.readAttachments({ validateCrcs: true })) attachments.push(a);
    return { reader, messages, metadata, attachments };
  } finally {
    await handle.close();
  }
}

// The whole file through McapStreamReader, in pieces; the CRCs of `footer` checked on the way.
function readStream(file, decompressHandlers, McapStreamReader, indexed) {
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  const out = { header: undefined, schemas: new Map(), channels: new Map(), messages: [], metadata: [], attachments: [], dataEnd: undefined };
  const dataCrc = new RangeCrc(0, Number(indexed.dataEndOffset));
  const footerOffset = Number(indexed.size) - 8 - 29;
  const summaryCrc = new RangeCrc(Number(indexed.reader.footer.summaryStart), footerOffset + 25);
  const fd = fs.openSync(file, "r");
  try {
    const piece = new Uint8Array(1 << 20);
    let position = 0;
    for (;;) {
      const n = fs.readSync(fd, piece, 0, piece.length, position);
      if (n === 0) break;
      const bytes = piece.slice(0, n);
      dataCrc.update(bytes, position);
      summaryCrc.update(bytes, position);
      position += n;
      stream.append(bytes);
      for (let record; (record = stream.nextRecord()); ) {
        if (record.type === "Header") out.header = record;
        else if (record.type === "Schema") out.schemas.set(record.id, record);
        else if (record.type === "Channel") out.channels.set(record.id, record);
        else if (record.type === "Message") out.messages.push(record);
        else if (record.type === "Metadata") out.metadata.push(record);
        else if (record.type === "Attachment") out.attachments.push(record);
        else if (record.type === "DataEnd") out.dataEnd = record;
      }
    }
  } finally {
    fs.closeSync(fd);
  }
  if (!stream.done()) throw new Error("the stream reader did not reach the closing magic");
  if (out.dataEnd && out.dataEnd.dataSectionCrc !== 0 && out.dataEnd.dataSectionCrc !== dataCrc.value()) {
    throw new Error(`the data section's CRC ${dataCrc.value()} is not DataEnd's ${out.dataEnd.dataSectionCrc}`);
  }
  const footerCrc = indexed.reader.footer.summaryCrc;
  if (indexed.reader.footer.summaryStart !== 0n && footerCrc !== 0 && footerCrc !== summaryCrc.value()) {
    throw new Error(`the summary's CRC ${summaryCrc.value()} is not the footer's ${footerCrc}`);
  }
  return out;
}

function checkSame(indexed, streamed) {
  const a = [...indexed.messages].sort(compareMessages);
  const b = [...streamed.messages].sort(compareMessages);
  if (a.length !== b.length) throw new Error(`the indexed reader read ${a.length} messages, the stream reader ${b.length}`);
  for (let i = 0; i < a.length; i++) {
    const [x, y] = [a[i], b[i]];
    if (x.channelId !== y.channelId || x.sequence !== y.sequence || x.logTime !== y.logTime || x.publishTime !== y.publishTime || !sameBytes(x.data, y.data)) {
      throw new Error(`message ${i} in log-time order differs between the indexed and the stream reader (channel ${x.channelId} sequence ${x.sequence} against channel ${y.channelId} sequence ${y.sequence})`);
    }
  }
  for (const [id, channel] of indexed.reader.channelsById) {
    const other = streamed.channels.get(id);
    if (!other || other.topic !== channel.topic || other.schemaId !== channel.schemaId || other.messageEncoding !== channel.messageEncoding) {
      throw new Error(`channel ${id} (${channel.topic}) differs between the summary and the data section`);
    }
  }
  if (streamed.channels.size !== indexed.reader.channelsById.size) throw new Error("the summary and the data section list different channels");
  const names = (list) => JSON.stringify(list.map((m) => m.name));
  if (names(indexed.metadata) !== names(streamed.metadata)) throw new Error("the indexed and the stream reader read different metadata");
  if (names(indexed.attachments) !== names(streamed.attachments)) throw new Error("the indexed and the stream reader read different attachments");
  return a;
}

async function main() {
  const args = process.argv.slice(2);
  if (args.length !== 1) fail("usage: read_mcap.mjs FILE.mcap");
  const file = args[0];
  let modules;
  try {
    modules = {
      core: require("@mcap/core"),
      support: require("@mcap/support"),
      rosmsg: require("@foxglove/rosmsg"),
      cdr: require("@foxglove/rosmsg2-serialization"),
    };
  } catch (e) {
    fail(`cannot load the npm packages from ${VIEWER}/node_modules (run scripts/setup.sh, or npm ci in viewer/): ${e.message}`);
  }
  const { McapIndexedReader, McapStreamReader } = modules.core;
  const decompressHandlers = await modules.support.loadDecompressHandlers();
  let messages;
  let indexed;
  try {
    indexed = await readIndexed(file, decompressHandlers, McapIndexedReader);
    indexed.dataEndOffset = indexed.reader.dataEndOffset;
    indexed.size = BigInt(fs.statSync(file).size);
    const streamed = readStream(file, decompressHandlers, McapStreamReader, indexed);
    messages = checkSame(indexed, streamed);
  } catch (e) {
    fail(`${file}: ${e.message}`);
  }
  const { reader } = indexed;
  const decoders = new Map();  // schema id -> MessageReader
  const counts = {};
  for (const channel of reader.channelsById.values()) counts[channel.topic] = 0;
  const lines = [];
  for (const m of messages) {
    const channel = reader.channelsById.get(m.channelId);
    const schema = channel.schemaId !== 0 ? reader.schemasById.get(channel.schemaId) : undefined;
    counts[channel.topic] += 1;
    const line = { topic: channel.topic, schema: schema ? schema.name : null, log_time: m.logTime.toString(), publish_time: m.publishTime.toString(), sequence: m.sequence, message: null };
    try {
      if (schema && channel.messageEncoding === "cdr" && schema.encoding === "ros2msg") {
        if (!decoders.has(schema.id)) {
          const text = new TextDecoder("utf-8", { fatal: true }).decode(schema.data);
          decoders.set(schema.id, new modules.cdr.MessageReader(modules.rosmsg.parse(text, { ros2: true })));
        }
        line.message = toJson(decoders.get(schema.id).readMessage(m.data));
      } else {
        line.data = { length: m.data.length, sha256: sha256(m.data) };
      }
    } catch (e) {
      fail(`${file}: message ${m.sequence} on ${channel.topic} (${schema ? schema.name : "no schema"}): cannot decode: ${e.message}`);
    }
    lines.push(JSON.stringify(line));
  }
  const metadata = {};
  for (const m of indexed.metadata) metadata[m.name] = Object.fromEntries(m.metadata);
  const summary = {
    messages: messages.length,
    channels: counts,
    metadata,
    attachments: indexed.attachments.map((a) => a.name),
    profile: reader.header.profile,
    library: reader.header.library,
  };
  lines.push(JSON.stringify({ summary }));
  process.stdout.write(lines.join("\n") + "\n");
}

main().catch((e) => fail(e && e.stack ? e.stack : String(e)));
