#!/usr/bin/env node
// corridorsim's MCAP files read by the ecosystem's readers (CTest recordings.mcap_read_by_foxglove):
// write_mcap_fixture writes the same recording in each compression, read_mcap.mjs reads it with
// @mcap/core (indexed and stream readers) and decodes it with @foxglove/rosmsg2-serialization, and
// every decoded value is checked against what write_mcap_fixture.cpp encodes. A cut file and a
// flipped byte inside a chunk must make read_mcap.mjs fail.
//
//   node tests/recordings/read_mcap_test.mjs WRITE_MCAP_FIXTURE WORK_DIR
//
// Exit 0: every check passed; 1: failures, one line each.

import { spawnSync } from "node:child_process";
import { createHash } from "node:crypto";
import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";

const HERE = path.dirname(fileURLToPath(import.meta.url));
const READ_MCAP = path.join(HERE, "read_mcap.mjs");
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

function main() {
  const [writer, workDir] = process.argv.slice(2);
  if (!writer || !workDir) {
    console.error("usage: read_mcap_test.mjs WRITE_MCAP_FIXTURE WORK_DIR");
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

  if (failures.length > 0) {
    for (const f of failures) console.error(`read_mcap_test: FAIL: ${f}`);
    process.exit(1);
  }
  console.log("read_mcap_test: every check passed");
}

main();
