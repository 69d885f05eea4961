#!/usr/bin/env node
// Validates a glTF 2.0 asset (.gltf or .glb) with Khronos' glTF-Validator (npm gltf-validator).
//
//   node tools/export-check/validate-gltf.mjs FILE
//
// Prints the validator's version, the counts of errors, warnings, infos and hints, then each
// error, warning and info with its code and JSON pointer. Exit status: 0 valid, 1 the validator
// found at least one error, 2 the input could not be read (or the validator could not parse
// the arguments or detect the format), 64 usage.
import { readFile } from 'node:fs/promises';
import path from 'node:path';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const validator = require('gltf-validator');

const args = process.argv.slice(2);
if (args.length !== 1 || args[0].startsWith('-')) {
  console.error('usage: validate-gltf.mjs FILE');
  process.exit(64);
}
const file = args[0];

let bytes;
try {
  bytes = new Uint8Array(await readFile(file));
} catch (error) {
  console.error(`validate-gltf: cannot read ${file}: ${error.message}`);
  process.exit(2);
}

let report;
try {
  report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0, // 0: no limit
    // Buffers and images the asset names by relative URI (clothbake embeds its buffers as
    // data: URIs, which the validator decodes itself).
    externalResourceFunction: (uri) =>
      readFile(path.resolve(path.dirname(file), decodeURIComponent(uri))).then(
        (data) => new Uint8Array(data),
        (error) => Promise.reject(error.message),
      ),
  });
} catch (error) {
  console.error(`validate-gltf: ${file} is unreadable as glTF: ${error}`);
  process.exit(2);
}

const issues = report.issues;
console.log(`glTF-Validator ${validator.version()}: ${file}`);
console.log(
  `${issues.numErrors} errors, ${issues.numWarnings} warnings, ${issues.numInfos} infos, ` +
    `${issues.numHints} hints` + (issues.truncated ? ' (truncated)' : ''),
);
const severities = ['error', 'warning', 'info', 'hint'];
for (const issue of issues.messages) {
  if (issue.severity > 2) continue; // hints are only counted
  const where = issue.pointer ?? (issue.offset !== undefined ? `byte ${issue.offset}` : '');
  console.log(`${severities[issue.severity]}: ${issue.code} at ${where || '(asset)'}: ${issue.message}`);
}
if (report.info) {
  const info = report.info;
  const used = (info.extensionsUsed ?? []).join(', ') || 'none';
  console.log(`extensions used: ${used}`);
}
process.exit(issues.numErrors > 0 ? 1 : 0);
