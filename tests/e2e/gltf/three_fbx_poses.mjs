// node three_fbx_poses.mjs FILE.fbx FRAMES OUT.json FPS: loads a binary FBX with three.js's
// FBXLoader (parse on an ArrayBuffer: no DOM needed without textures), plays its first
// animation with an AnimationMixer (LoopOnce, clamped) and writes, for frames 0..FRAMES-1 at
// the file's frame rate from the clip's start, the world position of every named object
// (bones and Nulls): {"fps", "poses": [{name: [x, y, z]}, ...]}.
import { readFileSync, writeFileSync } from 'node:fs';
import * as THREE from 'three';
import { FBXLoader } from 'three/examples/jsm/loaders/FBXLoader.js';

const [path, framesText, outPath, fpsText] = process.argv.slice(2);
// A camera in the file asks the browser window's size for its aspect: any will do here.
globalThis.window = { innerWidth: 1920, innerHeight: 1080 };
const bytes = readFileSync(path);
const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
const scene = new FBXLoader().parse(buffer, '');
const clip = scene.animations[0];
const mixer = new THREE.AnimationMixer(scene);
const action = mixer.clipAction(clip);
action.setLoop(THREE.LoopOnce, 1);
action.clampWhenFinished = true;
action.play();
const fps = Number(fpsText);
const poses = [];
const p = new THREE.Vector3();
for (let k = 0; k < Number(framesText); ++k) {
  mixer.setTime(k / fps);
  scene.updateMatrixWorld(true);
  const pose = {};
  scene.traverse((o) => {
    if (!o.name) return;
    o.getWorldPosition(p);
    pose[o.name] = [p.x, p.y, p.z];
  });
  poses.push(pose);
}
writeFileSync(outPath, JSON.stringify({ fps, duration: clip.duration, poses }));
