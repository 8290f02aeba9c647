#!/usr/bin/env node
// Validates glTF files with the Khronos glTF-Validator (npm package gltf-validator, installed
// into target/gltf-validator by `make setup`). Usage: node scripts/validate_gltf.js FILE...
// Prints one JSON line per file: {"file", "errors", "warnings", "infos", "hints", "messages"}
// (messages: the errors and warnings); exits 1 when any file has an error or a warning, 3 when
// the validator is not installed.
'use strict';
const fs = require('fs');
const path = require('path');

const dir = process.env.GLTF_VALIDATOR_DIR ||
  path.join(__dirname, '..', 'target', 'gltf-validator', 'node_modules', 'gltf-validator');
let validator;
try {
  validator = require(dir);
} catch (e) {
  console.error(`gltf-validator is not installed at ${dir}; run \`make setup\``);
  process.exit(3);
}

(async () => {
  let bad = false;
  for (const file of process.argv.slice(2)) {
    const bytes = new Uint8Array(fs.readFileSync(file));
    const report = await validator.validateBytes(bytes, { uri: path.basename(file), maxIssues: 100 });
    const i = report.issues;
    const messages = i.messages.filter((m) => m.severity <= 1);
    console.log(JSON.stringify({
      file, errors: i.numErrors, warnings: i.numWarnings, infos: i.numInfos, hints: i.numHints, messages,
    }));
    bad = bad || i.numErrors > 0 || i.numWarnings > 0;
  }
  process.exit(bad ? 1 : 0);
})().catch((e) => { console.error(e); process.exit(2); });
