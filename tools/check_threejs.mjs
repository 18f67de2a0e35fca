// three.js reads articula's BVH and glTF as articula means them.
//
// For each take: articula writes it as BVH (`smooth --smooth none`: the take as articula
// understands it, written as portable BVH), as glTF (`export gltf`) and its joint centres
// (`export positions`, m, the take's axes). three.js's BVHLoader and GLTFLoader load the two
// files in node, an AnimationMixer poses them at sampled frames, and every joint's world
// position must equal articula's within TOL_M: the BVH's, times the take's scale, equal
// articula's own reading of that BVH (`export positions OUT.bvh --keep-first-frame`; three.js
// adds position channels to the OFFSET, articula decides per joint), the glTF's the take's
// joint centres after the turn to glTF's +Y up (C, as src/pipeline/animation.rs's TO_Y_UP).
//
// Besides the takes given, a synthetic take whose root position channels replace the OFFSET
// (the convention three.js does not follow) is always checked.
//
// usage: THREE_DIR=<folder with node_modules/three> node tools/check_threejs.mjs ARTICULA [TAKE...]
// Exit status 1 on a disagreement, 2 on a usage or tool error.

import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, basename } from 'node:path';
import { pathToFileURL } from 'node:url';

const TOL_M = 1e-4; // 0.1 mm: the BVH's printed precision and glTF's f32 are far below it

const [articula, ...takes] = process.argv.slice(2);
const threeDir = process.env.THREE_DIR;
if (!articula || !threeDir) {
  console.error('usage: THREE_DIR=DIR node tools/check_threejs.mjs ARTICULA [TAKE...]');
  process.exit(2);
}
const mod = (p) => import(pathToFileURL(join(threeDir, 'node_modules/three', p)).href);
const THREE = await mod('build/three.module.js');
const { BVHLoader } = await mod('examples/jsm/loaders/BVHLoader.js');
const { GLTFLoader } = await mod('examples/jsm/loaders/GLTFLoader.js');

const work = mkdtempSync(join(tmpdir(), 'articula-three-'));
const run = (...args) => execFileSync(articula, args, { encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe'] });

// a replace-convention take: the root's channels hold its position, the OFFSET its rest place
function replaceTake() {
  const rows = [];
  for (let k = 0; k < 30; k++) {
    const s = Math.sin(k / 5), c = Math.cos(k / 5);
    rows.push([20 + 30 * s, 95 + 2 * c, 40 + 10 * k, 5 * s, 20 * c, 3, 10 * s, 0, 0, 30 * s, 0, 0,
      -10 * s, 0, 0, 30 * c, 0, 0, 5, 5 * c, 0].map((v) => v.toFixed(4)).join(' '));
  }
  const text = `HIERARCHY
ROOT Hips
{
  OFFSET 20 95 40
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT LeftUpLeg
  {
    OFFSET 10 0 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT LeftLeg
    {
      OFFSET 0 -45 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      End Site
      {
        OFFSET 0 -45 0
      }
    }
  }
  JOINT RightUpLeg
  {
    OFFSET -10 0 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT RightLeg
    {
      OFFSET 0 -45 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      End Site
      {
        OFFSET 0 -45 0
      }
    }
  }
  JOINT Spine
  {
    OFFSET 0 10 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 60 0
    }
  }
}
MOTION
Frames: ${rows.length}
Frame Time: 0.033333
${rows.join('\n')}
`;
  const path = join(work, 'replace_root.bvh');
  writeFileSync(path, text);
  return path;
}

// articula's joint centres: rows of [time, x, y, z per joint], names from the header
// (`pos:<joint>:x|y|z`, articula's one column scheme)
function positionsCsv(path) {
  const [head, ...rows] = readFileSync(path, 'utf8').trim().split('\n');
  const cols = head.split(',');
  const names = [];
  for (let i = 1; i < cols.length; i += 3) names.push(cols[i].replace(/^pos:/, '').slice(0, -2));
  return { names, rows: rows.map((r) => r.split(',').map(Number)) };
}

const UP = { // rows of C, glTF axes from the take's
  x: [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
  y: [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
  z: [[1, 0, 0], [0, 0, 1], [0, -1, 0]],
};

// world positions of named nodes under `root` after the mixer is set to `time`
function pose(root, clip, time, names) {
  const mixer = new THREE.AnimationMixer(root);
  const action = mixer.clipAction(clip);
  action.setLoop(THREE.LoopOnce, 1);
  action.clampWhenFinished = true;
  action.play();
  mixer.setTime(time);
  root.updateMatrixWorld(true);
  const out = new Map();
  root.traverse((o) => { if (names.has(o.name)) out.set(o.name, o.getWorldPosition(new THREE.Vector3())); });
  return out;
}

// GLTFLoader names nodes as PropertyBinding.sanitizeNodeName does (`pelvis.R` → `pelvisR`,
// `mixamorig:Hips` → `mixamorigHips`), so that animation tracks can address them
const sanitized = (n) => THREE.PropertyBinding.sanitizeNodeName(n);

function compare(label, got, want, frame, rename = (n) => n) {
  let worst = 0, where = '';
  for (const [name, w] of want) {
    const g = got.get(rename(name));
    if (!g) throw new Error(`${label}: joint ${name} missing`);
    const e = Math.hypot(g.x - w[0], g.y - w[1], g.z - w[2]);
    if (e > worst) { worst = e; where = `${name} at frame ${frame}`; }
  }
  return { worst, where };
}

async function check(take) {
  const stem = basename(take, '.bvh');
  let info;
  try {
    info = JSON.parse(run('info', take, '--json'));
  } catch (e) {
    // a take articula refuses (with its clear error) has no output to check
    console.log(`skip three.js ${stem}: articula refuses it: ${String(e.stderr ?? e).trim().split('\n').pop()}`);
    return true;
  }
  const bvhPath = join(work, `${stem}.bvh`), glbPath = join(work, `${stem}.glb`), csvPath = join(work, `${stem}.csv`);
  run('smooth', take, '--smooth', 'none', '-o', bvhPath);
  run('export', 'gltf', take, '-o', glbPath);
  run('export', 'positions', take, '-o', csvPath);
  // the BVH against articula's reading of that same file (a joint `smooth` welds as a prop
  // keeps its rest rotation there), the glTF against the take's
  const bvhCsv = join(work, `${stem}.out.csv`);
  run('export', 'positions', bvhPath, '--keep-first-frame', '-o', bvhCsv);
  const centres = positionsCsv(csvPath);
  const ownReading = positionsCsv(bvhCsv);
  if (ownReading.rows.length !== centres.rows.length) throw new Error(`${stem}: articula reads ${ownReading.rows.length} frames back from its BVH, wrote ${centres.rows.length}`);
  const saneNames = new Set(centres.names.map(sanitized));
  const n = centres.rows.length;
  const frames = [...new Set([0, Math.floor(n / 3), Math.floor((2 * n) / 3), n - 1])];

  // BVH: file units, the take's axes, frame k at k·dt
  const bvh = new BVHLoader().parse(readFileSync(bvhPath, 'utf8'));
  // BVHLoader names bones and tracks as the file does, and PropertyBinding cannot address a
  // name with `.` `:` `/` `[` `]` (Mixamo's `mixamorig:Hips`, MakeHuman's `pelvis.R`): three.js
  // leaves such bones unanimated. Rename them as GLTFLoader does, so the file's numbers are
  // what is checked.
  for (const bone of bvh.skeleton.bones) bone.name = sanitized(bone.name);
  for (const track of bvh.clip.tracks) {
    const at = track.name.lastIndexOf('.');
    track.name = `${sanitized(track.name.slice(0, at))}${track.name.slice(at)}`;
  }
  const holder = new THREE.Object3D();
  holder.add(bvh.skeleton.bones[0]);
  const dt = bvh.clip.tracks[0].times[1] ?? 0;
  // glTF: m, +Y up, keys at the file's times
  const buf = readFileSync(glbPath);
  const gltf = await new Promise((ok, fail) =>
    new GLTFLoader().parse(buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.byteLength), '', ok, fail));
  const times = gltf.animations[0].tracks[0].times;
  const C = UP[info.up];
  const result = { bvh: { worst: 0, where: '' }, glb: { worst: 0, where: '' } };
  for (const k of frames) {
    const row = centres.rows[k];
    const want = new Map(centres.names.map((nm, j) => [nm, row.slice(1 + 3 * j, 4 + 3 * j)]));
    const own = ownReading.rows[k];
    const wantBvh = new Map(ownReading.names.map((nm, j) => [nm, own.slice(1 + 3 * j, 4 + 3 * j)]));
    const scaled = pose(holder, bvh.clip, k * dt, saneNames);
    for (const v of scaled.values()) v.multiplyScalar(info.scale_to_m);
    const b = compare(`${stem}.bvh`, scaled, wantBvh, k, sanitized);
    const turned = new Map([...want].map(([nm, p]) => [nm, C.map((r) => r[0] * p[0] + r[1] * p[1] + r[2] * p[2])]));
    const g = compare(`${stem}.glb`, pose(gltf.scene, gltf.animations[0], times[k], saneNames), turned, k, sanitized);
    for (const [key, r] of [['bvh', b], ['glb', g]]) if (r.worst >= result[key].worst) result[key] = r;
  }
  let ok = true;
  for (const key of ['bvh', 'glb']) {
    const r = result[key];
    const pass = r.worst <= TOL_M;
    ok &&= pass;
    console.log(`${pass ? 'ok  ' : 'FAIL'} three.js ${key} ${stem}: ${centres.names.length} joints, frames ${frames.join(',')}: max |Δ| ${(r.worst * 1000).toFixed(4)} mm${r.worst > 0 ? ` (${r.where})` : ''} (tolerance ${TOL_M * 1000} mm)`);
  }
  return ok;
}

let ok = true;
for (const take of [replaceTake(), ...takes]) {
  try {
    ok = (await check(take)) && ok;
  } catch (e) {
    console.log(`FAIL three.js ${take}: ${e.message ?? e}`);
    ok = false;
  }
}
process.exit(ok ? 0 : 1);
