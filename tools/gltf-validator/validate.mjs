// Validates glTF files with the Khronos glTF validator and prints one JSON report a
// file ({"file", "numErrors", "numWarnings", "messages"}); exits 1 if any has errors.
// Usage: node tools/gltf-validator/validate.mjs FILE.glb [FILE.glb ...]
import { readFile } from "node:fs/promises";
import validator from "gltf-validator";

let failed = false;
for (const file of process.argv.slice(2)) {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, { maxIssues: 50 });
  const { numErrors, numWarnings, messages } = report.issues;
  console.log(JSON.stringify({ file, numErrors, numWarnings, messages }));
  if (numErrors > 0) failed = true;
}
process.exit(failed ? 1 : 0);
