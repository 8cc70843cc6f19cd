// Validates a .glb with the Khronos glTF validator and prints its report as JSON.
//
//     node validate_gltf.mjs FILE.glb
//
// The validator is the npm package gltf-validator installed in tools/gltf-validator at the
// repository root (npm ci --prefix tools/gltf-validator), or in the directory
// RELIEF_GLTF_VALIDATOR_DIR names. Exits with 3 (after saying so on stderr) when it is not
// installed, 2 when the file cannot be read or validated at all.
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { basename, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const toolDir =
    process.env.RELIEF_GLTF_VALIDATOR_DIR ||
    fileURLToPath(new URL('../../../tools/gltf-validator/', import.meta.url));
let validator;
try {
    validator = createRequire(join(toolDir, 'package.json'))('gltf-validator');
} catch (error) {
    console.error(`gltf-validator is not installed in ${toolDir}: ${error.message}`);
    process.exit(3);
}

const file = process.argv[2];
try {
    const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
        uri: basename(file),
        maxIssues: 100,
    });
    console.log(JSON.stringify(report));
} catch (error) {
    console.error(`cannot validate ${file}: ${error}`);
    process.exit(2);
}
