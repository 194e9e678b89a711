// Validates a .glb with the Khronos glTF validator (npm package gltf-validator).
// Usage: node validate_gltf.js <node_modules folder> <file.glb>
// Prints the report as JSON; exits 1 if it lists errors, 2 on a failure to run.
const path = require('path');
const fs = require('fs');
const validator = require(path.join(process.argv[2], 'gltf-validator'));
const bytes = new Uint8Array(fs.readFileSync(process.argv[3]));
validator.validateBytes(bytes, {maxIssues: 100})
    .then((report) => {
      console.log(JSON.stringify(report, null, 1));
      process.exit(report.issues.numErrors > 0 ? 1 : 0);
    })
    .catch((error) => {
      console.error(error);
      process.exit(2);
    });
