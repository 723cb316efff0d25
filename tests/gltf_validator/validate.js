// Runs the Khronos glTF Validator (npm package gltf-validator) on one .glb file and prints
// its report as JSON. Exit status: 0 when the report has no errors, 1 when it has some,
// 3 when the package is not installed (the Rust test then says so and skips).
//
// usage: node tests/gltf_validator/validate.js FILE.glb
'use strict';
const fs = require('fs');
const path = require('path');

let validator;
try {
  validator = require('gltf-validator');
} catch (e) {
  // Also look where .ci/run installs it.
  try {
    validator = require(path.join(__dirname, 'node_modules', 'gltf-validator'));
  } catch (e2) {
    console.error('gltf-validator is not installed');
    process.exit(3);
  }
}

const file = process.argv[2];
const bytes = new Uint8Array(fs.readFileSync(file));
validator
  .validateBytes(bytes, { maxIssues: 0 })
  .then((report) => {
    console.log(JSON.stringify(report, null, 1));
    process.exit(report.issues.numErrors === 0 ? 0 : 1);
  })
  .catch((error) => {
    console.error('validator failed: ' + error);
    process.exit(2);
  });
