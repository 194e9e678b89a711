// Validates a .glb or .gltf with the Khronos glTF validator (npm package
// gltf-validator); a .gltf's buffers and images are read from its folder.
// Usage: node validate_gltf.js <node_modules folder> <file.glb|file.gltf>
// Prints the report as JSON; exits 1 if it lists errors, 2 on a failure to run.
const path = require('path');
const fs = require('fs');
const validator = require(path.join(process.argv[2], 'gltf-validator'));
const file = process.argv[3];
const bytes = new Uint8Array(fs.readFileSync(file));
const options = {
  maxIssues: 100,
  uri: path.basename(file),
  externalResourceFunction: (uri) => new Promise((resolve, reject) => {
    fs.readFile(path.join(path.dirname(file), decodeURIComponent(uri)),
                (error, data) => error ? reject(error.toString()) : resolve(new Uint8Array(data)));
  }),
};
validator.validateBytes(bytes, options)
    .then((report) => {
      console.log(JSON.stringify(report, null, 1));
      process.exit(report.issues.numErrors > 0 ? 1 : 0);
    })
    .catch((error) => {
      console.error(error);
      process.exit(2);
    });
