#!/usr/bin/env node
// corridorsim's MCAP files read by the ecosystem's readers (CTest recordings.mcap_read_by_foxglove):
// write_mcap_fixture writes the same recording in each compression, read_mcap.mjs reads it with
// @mcap/core (indexed and stream readers) and decodes it with @foxglove/rosmsg2-serialization, and
// every decoded value is checked against what write_mcap_fixture.cpp encodes. A cut file and a
// flipped byte inside a chunk must make read_mcap.mjs fail. The other way round, files
// @mcap/core's McapWriter writes (schemas and channels inside the chunks; with a summary, without
// one, cut short) must read the same through corridorsim's reader (dump_mcap).
//
//   node tests/recordings/read_mcap_test.mjs WRITE_MCAP_FIXTURE DUMP_MCAP WORK_DIR
//
// Exit 0: every check passed; 1: failures, one line each.

import { spawnSync } from "node:child_process";
import { createHash } from "node:crypto";
import fs from "node:fs";
import { createRequire } from "node:module";
import path from "node:path";
import { fileURLToPath } from "node:url";

const HERE = path.dirname(fileURLToPath(import.meta.url));
const READ_MCAP = path.join(HERE, "read_mcap.mjs");
const require = createRequire(path.join(HERE, "..", "..", "viewer", "package.json"));
const failures = [];

function check(condition, what) {
  if (!condition) failures.push(what);
  return condition;
}

function sha256(bytes) {
  return createHash("sha256").update(Uint8Array.from(bytes)).digest("hex");
}

function run(command, args) {
  return spawnSync(command, args, { encoding: "utf8", maxBuffer: 64 << 20 });
}

// What write_mcap_fixture.cpp writes (see its header comment).
const T0 = 1700000000000000000n;
function chatterTime(i) {
  return T0 + BigInt(i) * 10000000n - (i % 2 === 1 ? 15000000n : 0n);
}

function checkLines(name, lines) {
  const summary = lines.pop().summary;
  const expectedSummary = {
    messages: 53,
    channels: { "/chatter": 30, "/samples": 20, "/raw": 3 },
    metadata: { corridorsim: { scenario: "fixture", seed: "7" } },
    attachments: ["scenario.yaml"],
    profile: "ros2",
    library: "corridorsim",
  };
  check(JSON.stringify(summary) === JSON.stringify(expectedSummary), `${name}: summary ${JSON.stringify(summary)}`);
  check(lines.length === 53, `${name}: ${lines.length} message lines, not 53`);
  for (let k = 1; k < lines.length; k++) {
    check(BigInt(lines[k - 1].log_time) <= BigInt(lines[k].log_time), `${name}: line ${k} is out of log-time order`);
  }
  for (const line of lines) {
    const i = line.sequence;
    const where = `${name}: ${line.topic} sequence ${i}`;
    if (line.topic === "/chatter") {
      check(line.schema === "std_msgs/msg/String", `${where}: schema ${line.schema}`);
      check(line.log_time === chatterTime(i).toString(), `${where}: log_time ${line.log_time}`);
      check(line.publish_time === (chatterTime(i) + 1n).toString(), `${where}: publish_time ${line.publish_time}`);
      check(JSON.stringify(line.message) === JSON.stringify({ data: `hello ${i}` }), `${where}: ${JSON.stringify(line.message)}`);
    } else if (line.topic === "/samples") {
      const blob = Array.from({ length: 100 + i }, (_, k) => (i + k) % 256);
      const expected = {
        values: [1.5, -2.25, "inf", "-inf", "nan", 1e300, i],
        blob: { length: blob.length, sha256: sha256(blob) },
        stamp: (2n ** 62n + BigInt(i)).toString(),
        label: `sample \u00fc ${i}`,
      };
      check(line.schema === "corridorsim_test_msgs/msg/Samples", `${where}: schema ${line.schema}`);
      check(line.log_time === (chatterTime(i) + 5n).toString(), `${where}: log_time ${line.log_time}`);
      check(JSON.stringify(line.message) === JSON.stringify(expected), `${where}: ${JSON.stringify(line.message)}`);
    } else if (line.topic === "/raw") {
      check(line.schema === null && line.message === null, `${where}: decoded without a schema`);
      check(JSON.stringify(line.data) === JSON.stringify({ length: 3, sha256: sha256([i * 10, 0, 255]) }), `${where}: data ${JSON.stringify(line.data)}`);
      check(line.log_time === (chatterTime(i * 10) + 7n).toString(), `${where}: log_time ${line.log_time}`);
    } else {
      check(false, `${where}: unknown topic`);
    }
  }
}

function expectFailure(name, file) {
  const result = run(process.execPath, [READ_MCAP, file]);
  check(result.status === 1, `${name}: read_mcap.mjs exited ${result.status}, not 1`);
  check(/^read_mcap: /.test(result.stderr) && result.stderr.trim().split("\n").length === 1, `${name}: message ${JSON.stringify(result.stderr)}`);
}

// A file written by @mcap/core's McapWriter: three channels registered as they start (so their
// records go into the chunks), log times out of order, metadata and an attachment. Returns the
// messages in the order written.
async function writeWithMcapCore(file, options) {
  const { McapWriter } = require("@mcap/core");
  const fd = fs.openSync(file, "w");
  let position = 0n;
  const writable = {
    position: () => position,
    write: async (buffer) => {
      fs.writeSync(fd, buffer);
      position += BigInt(buffer.byteLength);
    },
  };
  const writer = new McapWriter({ writable, chunkSize: 700, ...options });
  await writer.start({ profile: "ros2", library: "mcap-core-test" });
  const written = [];
  const channels = [];
  const sequences = [];
  for (let i = 0; i < 60; i++) {
    if (i % 20 === 0) {
      const k = channels.length;
      const schemaId = await writer.registerSchema({ name: `test_msgs/msg/T${k}`, encoding: "ros2msg", data: new TextEncoder().encode(`uint8[] data${k}\n`) });
      channels.push(await writer.registerChannel({ topic: `/topic${k}`, schemaId, messageEncoding: "cdr", metadata: new Map([["k", String(k)]]) }));
      sequences.push(0);
    }
    const c = i % channels.length;
    const logTime = 5000000000n + BigInt(i) * 1000n - (i % 3 === 2 ? 2500n : 0n);
    const data = Uint8Array.from({ length: 20 + ((i * 13) % 50) }, (_, k) => (i * 31 + k) & 255);
    const message = { channelId: channels[c], sequence: sequences[c]++, logTime, publishTime: logTime + 3n, data };
    await writer.addMessage(message);
    written.push({ topic: `/topic${c}`, sequence: message.sequence, log_time: logTime.toString(), publish_time: (logTime + 3n).toString(), length: data.length, sha256: sha256(data) });
    if (i === 30) {
      await writer.addMetadata({ name: "run", metadata: new Map([["seed", "7"], ["scenario", "ts"]]) });
      await writer.addAttachment({ name: "notes.txt", mediaType: "text/plain", logTime: 1n, createTime: 2n, data: new TextEncoder().encode("notes\n") });
    }
  }
  await writer.end();
  fs.closeSync(fd);
  return written;
}

function dump(dumper, file) {
  const result = run(dumper, [file, "notes.txt"]);
  if (result.status !== 0) return { error: `dump_mcap exited ${result.status}: ${result.stderr}` };
  const lines = result.stdout.trim().split("\n").map((l) => JSON.parse(l));
  return { summary: lines.pop().summary, messages: lines };
}

async function checkEcosystemFiles(dumper, workDir) {
  const noSummary = { useStatistics: false, useSummaryOffsets: false, repeatSchemas: false, repeatChannels: false, useAttachmentIndex: false, useMetadataIndex: false, useChunkIndex: false, useMessageIndex: false };
  for (const [name, options] of [["with_summary", {}], ["without_summary", noSummary]]) {
    const file = path.join(workDir, `mcap_core_${name}.mcap`);
    const written = await writeWithMcapCore(file, options);
    const read = dump(dumper, file);
    if (!check(!read.error, `${name}: ${read.error}`)) continue;
    check(JSON.stringify(read.messages) === JSON.stringify(written), `${name}: corridorsim's reader read other messages than @mcap/core wrote`);
    const s = read.summary;
    check(s.truncated === false && s.profile === "ros2" && s.library === "mcap-core-test", `${name}: header ${JSON.stringify(s)}`);
    check(JSON.stringify(s.counts) === JSON.stringify({ "/topic0": 36, "/topic1": 17, "/topic2": 7 }), `${name}: counts ${JSON.stringify(s.counts)}`);
    check(Object.keys(s.schemas).length === 3 && Object.keys(s.channels).length === 3, `${name}: schemas ${JSON.stringify(s.schemas)}`);
    check(JSON.stringify(s.metadata) === JSON.stringify([["run", { scenario: "ts", seed: "7" }]]), `${name}: metadata ${JSON.stringify(s.metadata)}`);
    check(s.attachment && s.attachment.length === 6 && s.attachment.media_type === "text/plain", `${name}: attachment ${JSON.stringify(s.attachment)}`);
    if (name !== "with_summary") continue;
    // Cut at 60%: the messages of the complete chunks before the cut, in order.
    const bytes = fs.readFileSync(file);
    const cut = path.join(workDir, "mcap_core_cut.mcap");
    fs.writeFileSync(cut, bytes.subarray(0, Math.floor(bytes.length * 0.6)));
    const partial = dump(dumper, cut);
    if (!check(!partial.error, `cut: ${partial.error}`)) continue;
    check(partial.summary.truncated === true, "cut: not reported truncated");
    check(partial.messages.length > 10 && partial.messages.length < written.length, `cut: ${partial.messages.length} messages`);
    check(JSON.stringify(partial.messages) === JSON.stringify(written.slice(0, partial.messages.length)), "cut: the messages read are not the first ones written");
  }
}

async function main() {
  const [writer, dumper, workDir] = process.argv.slice(2);
  if (!writer || !dumper || !workDir) {
    console.error("usage: read_mcap_test.mjs WRITE_MCAP_FIXTURE DUMP_MCAP WORK_DIR");
    process.exit(2);
  }
  fs.rmSync(workDir, { recursive: true, force: true });
  fs.mkdirSync(workDir, { recursive: true });
  const outputs = {};
  for (const compression of ["none", "zstd", "lz4"]) {
    const file = path.join(workDir, `${compression}.mcap`);
    const written = run(writer, [file, compression]);
    if (!check(written.status === 0, `${compression}: write_mcap_fixture exited ${written.status}: ${written.stderr}`)) continue;
    const read = run(process.execPath, [READ_MCAP, file]);
    if (!check(read.status === 0, `${compression}: read_mcap.mjs exited ${read.status}: ${read.stderr}`)) continue;
    outputs[compression] = read.stdout;
    checkLines(compression, read.stdout.trim().split("\n").map((l) => JSON.parse(l)));
  }
  check(outputs.none === outputs.zstd && outputs.none === outputs.lz4, "the three compressions read differently");

  const bytes = fs.readFileSync(path.join(workDir, "none.mcap"));
  const cut = path.join(workDir, "cut.mcap");
  fs.writeFileSync(cut, bytes.subarray(0, Math.floor(bytes.length / 2)));
  expectFailure("a file cut in half", cut);
  const flipped = Buffer.from(bytes);
  const at = flipped.indexOf("hello 5");  // inside an uncompressed chunk: its CRC must catch it
  check(at > 0, "no 'hello 5' in none.mcap");
  flipped[at] ^= 0x20;
  const flippedFile = path.join(workDir, "flipped.mcap");
  fs.writeFileSync(flippedFile, flipped);
  expectFailure("a flipped byte in a chunk", flippedFile);
  expectFailure("a missing file", path.join(workDir, "none_such.mcap"));
  await checkEcosystemFiles(dumper, workDir);

  if (failures.length > 0) {
    for (const f of failures) console.error(`read_mcap_test: FAIL: ${f}`);
    process.exit(1);
  }
  console.log("read_mcap_test: every check passed");
}

main().catch((e) => {
  console.error(`read_mcap_test: FAIL: ${e && e.stack ? e.stack : e}`);
  process.exit(1);
});
