// node three_poses.mjs FILE FPS OUT.json FRAMES [HALF]: loads a glTF file with three.js's
// GLTFLoader (parse on an ArrayBuffer: no DOM needed without textures), plays its first
// animation with an AnimationMixer (LoopOnce, clamped at the end) and writes, for each listed
// frame k, the world position of every named node and every mesh's morph influences at
// first key + k / FPS seconds. With HALF, also at first key + (k + 0.5) / FPS under "k.5".
import { readFileSync, writeFileSync } from 'node:fs';
import * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';

const [path, fpsText, outPath, framesText, half] = process.argv.slice(2);
const fps = Number(fpsText);
const frames = framesText.split(',').map(Number);
// GLTFLoader fetches a .gltf's data: URIs through FileLoader, which needs a browser's
// ProgressEvent: a .gltf with one embedded buffer is handed over as the equivalent GLB.
function asGlb(bytes) {
  if (bytes.subarray(0, 4).toString('latin1') === 'glTF') return bytes;
  const json = JSON.parse(bytes.toString('utf8'));
  if (json.buffers.length !== 1) throw new Error(`${path}: expected one buffer`);
  const uri = json.buffers[0].uri;
  const bin = Buffer.from(uri.slice(uri.indexOf(',') + 1), 'base64');
  delete json.buffers[0].uri;
  let text = Buffer.from(JSON.stringify(json), 'utf8');
  text = Buffer.concat([text, Buffer.alloc((4 - (text.length % 4)) % 4, 0x20)]);
  const padded = Buffer.concat([bin, Buffer.alloc((4 - (bin.length % 4)) % 4)]);
  const header = Buffer.alloc(12);
  header.write('glTF', 0, 'latin1');
  header.writeUInt32LE(2, 4);
  header.writeUInt32LE(12 + 8 + text.length + 8 + padded.length, 8);
  const chunk = (length, type) => {
    const b = Buffer.alloc(8);
    b.writeUInt32LE(length, 0);
    b.write(type, 4, 'latin1');
    return b;
  };
  return Buffer.concat([header, chunk(text.length, 'JSON'), text,
    chunk(padded.length, 'BIN\0'), padded]);
}
const bytes = asGlb(readFileSync(path));
const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);

const gltf = await new Promise((resolve, reject) =>
  new GLTFLoader().parse(buffer, '', resolve, reject));
const clip = gltf.animations[0];
let first = Infinity;
for (const track of clip.tracks) first = Math.min(first, track.times[0]);
const mixer = new THREE.AnimationMixer(gltf.scene);
const action = mixer.clipAction(clip);
action.setLoop(THREE.LoopOnce, 1);
action.clampWhenFinished = true;
action.play();

function pose(time) {
  mixer.setTime(time);
  gltf.scene.updateMatrixWorld(true);
  const nodes = {};
  const morphs = {};
  const p = new THREE.Vector3();
  gltf.scene.traverse((o) => {
    if (o.isMesh && o.morphTargetInfluences) {
      morphs[o.name] = Array.from(o.morphTargetInfluences);
    } else if (o.name && !o.isMesh) {
      o.getWorldPosition(p);
      nodes[o.name] = [p.x, p.y, p.z];
    }
  });
  return { nodes, morphs };
}

const poses = {};
for (const k of frames) {
  poses[String(k)] = pose(first + k / fps);
  if (half) poses[`${k}.5`] = pose(first + (k + 0.5) / fps);
}
writeFileSync(outPath, JSON.stringify({ first, interpolations: [...new Set(clip.tracks.map(
  (t) => t.getInterpolation()))], poses }));
console.log(`poses ${frames.length} from ${path}`);
