#!/usr/bin/env node
// Does this Node.js satisfy the `engines.node` range of every package an npm lockfile pins?
// scripts/setup.sh runs it before `npm ci` in viewer/, so that a Node too old for the lockfile's
// packages (playwright-core refuses older ones at run time) fails there, with one message,
// instead of in a browser test.
//
//   node scripts/check_node_engines.js LOCKFILE [NODE_VERSION]
//
// NODE_VERSION (default: this node's, process.versions.node) is for the tests. Exit 0: every
// range is met; 1: some are not (one line per package, naming the lockfile); 2: a bad command line,
// an unreadable lockfile or a range this script cannot read. Plain ES5 on purpose: it has to run,
// and say why it fails, on an old Node.
"use strict";
var fs = require("fs");

function die(code, msg) {
  process.stderr.write("check_node_engines: " + msg + "\n");
  process.exit(code);
}

var args = process.argv.slice(2);
if (args.length < 1 || args.length > 2) die(2, "usage: check_node_engines.js LOCKFILE [NODE_VERSION]");
var lockPath = args[0];
var nodeVersion = args.length > 1 ? args[1] : process.versions.node;

/** "18.20.4" -> [18, 20, 4]; null when not a version. */
function parseVersion(s) {
  var m = /^v?(\d+)\.(\d+)\.(\d+)$/.exec(String(s).trim());
  return m ? [Number(m[1]), Number(m[2]), Number(m[3])] : null;
}

function compare(a, b) {
  for (var i = 0; i < 3; i++) if (a[i] !== b[i]) return a[i] < b[i] ? -1 : 1;
  return 0;
}

// One comparator of a range: op and a partial version ("20", "18.17", "18.17.0"; "x" or "*"
// for a missing part). Returns [lowest accepted, op, highest, ...] as a test function.
function comparator(text) {
  var m = /^(>=|<=|>|<|=|\^|~)?v?(\d+|[xX*])(?:\.(\d+|[xX*]))?(?:\.(\d+|[xX*]))?$/.exec(text);
  if (!m) return null;
  var op = m[1] || "";
  var parts = [m[2], m[3], m[4]];
  var given = 0;
  while (given < 3 && parts[given] !== undefined && !/^[xX*]$/.test(parts[given])) given++;
  var v = [0, 0, 0];
  for (var i = 0; i < given; i++) v[i] = Number(parts[i]);
  // the first version past the partial one: "18" -> 19.0.0, "18.17" -> 18.18.0
  function bump(k) { var u = v.slice(); if (k < 0) return null; u[k] += 1; for (var j = k + 1; j < 3; j++) u[j] = 0; return u; }
  var next = bump(given - 1);
  if (op === ">=") return function (n) { return compare(n, v) >= 0; };
  if (op === ">") return function (n) { return next ? compare(n, next) >= 0 : false; };
  if (op === "<") return function (n) { return compare(n, v) < 0; };
  if (op === "<=") return function (n) { return next ? compare(n, next) < 0 : true; };
  if (op === "^") {
    var k = v[0] > 0 || given <= 1 ? 0 : v[1] > 0 || given <= 2 ? 1 : 2;
    var top = bump(Math.min(k, given - 1));
    return function (n) { return compare(n, v) >= 0 && (!top || compare(n, top) < 0); };
  }
  if (op === "~") {
    var top2 = bump(given >= 2 ? 1 : given - 1);
    return function (n) { return compare(n, v) >= 0 && (!top2 || compare(n, top2) < 0); };
  }
  // "=", or no operator: the versions the partial one names
  return function (n) { return compare(n, v) >= 0 && (!next || compare(n, next) < 0); };
}

/** Whether version n satisfies the npm range text; throws on a form this script cannot read. */
function satisfies(n, range) {
  var alternatives = String(range).split("||");
  for (var a = 0; a < alternatives.length; a++) {
    var alt = alternatives[a].trim().replace(/(>=|<=|>|<|=|\^|~)\s+/g, "$1");
    if (alt === "" || alt === "*") return true;
    var hyphen = /^(\S+)\s+-\s+(\S+)$/.exec(alt);
    var tests = [];
    var words = hyphen ? [">=" + hyphen[1], "<=" + hyphen[2]] : alt.split(/\s+/);
    for (var w = 0; w < words.length; w++) {
      var c = comparator(words[w]);
      if (!c) throw new Error("cannot read the range '" + range + "'");
      tests.push(c);
    }
    if (tests.every(function (t) { return t(n); })) return true;
  }
  return false;
}

var have = parseVersion(nodeVersion);
if (!have) die(2, "not a Node.js version: '" + nodeVersion + "'");
var lock;
try {
  lock = JSON.parse(fs.readFileSync(lockPath, "utf8"));
} catch (e) {
  die(2, lockPath + ": " + e.message);
}
var packages = lock && typeof lock.packages === "object" && lock.packages;
if (!packages) die(2, lockPath + ": no \"packages\" object (lockfileVersion 2 or 3 expected)");

var problems = [];
Object.keys(packages).sort().forEach(function (key) {
  var p = packages[key];
  if (!key || !p || !p.engines || typeof p.engines !== "object" || p.engines.node === undefined) return;
  var name = key.replace(/^.*node_modules\//, "");
  var ok;
  try {
    ok = satisfies(have, p.engines.node);
  } catch (e) {
    die(2, lockPath + ": " + key + ": engines.node: " + e.message);
  }
  if (!ok) problems.push(name + " " + p.version + " needs Node.js " + p.engines.node);
});
if (problems.length) {
  problems.forEach(function (m) {
    process.stderr.write("check_node_engines: " + lockPath + ": " + m + "; this node (" +
      process.execPath + ") is " + nodeVersion + "\n");
  });
  process.exit(1);
}
