// The page of macsim_web: the world as three.js meshes (z up, REP-103), updated over a
// WebSocket; the robot with its crane, the laser's scan and cloud in the robot's frame, the
// stereo images, sim time and real-time factor; the simulator's camera modes; a controller's
// plan beside the view, and its labels over the things it judged.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

THREE.Object3D.DEFAULT_UP.set(0, 0, 1);

// What a test (or a curious user, in the console) can read.
const state = window.macsimView = {
  connected: false, domain: null, robot: null, drawn: 0, objectIds: [], robotKnown: false,
  robotPose: null, simTime: 0, rtf: 0, updates: 0, scans: 0, clouds: 0, images: 0,
  mode: 'Follow', errors: [],
  // A controller's plan (rt/<robot>/plan), when one publishes it: its round, steps, the step
  // under way, its outcome, and the labels drawn over the things it judged.
  plan: null,
  // Latency figures: for the object ids put in `watched`, every pose change the page applied,
  // as [wall time ms (Date.now()), x, y, z].
  watched: new Set(), changes: {},
};

// Drawn when something changed (an update, the mouse, a mode), not at the display's rate:
// a browser left open costs its machine little.
let dirty = true;

// The KURT3D's geometry (base_link: x forward, y left, z up), as its robot description says.
const KURT = {
  baseHeight: 0.167, pivot: [0.05, 0, 0.16], boom: 0.5, magnetBelowTip: 0.05,
  camera: [0.05, 0.06, 0.42], cameraPitch: 15 * Math.PI / 180, laserZ: 0.35,
};

const view = document.getElementById('view');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(1);
renderer.setSize(window.innerWidth, window.innerHeight);
view.appendChild(renderer.domElement);

const scene = new THREE.Scene();
scene.background = new THREE.Color(0x9fb4c8);
scene.add(new THREE.HemisphereLight(0xffffff, 0x50585f, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(4, -6, 10);
scene.add(sun);
const floor = new THREE.Mesh(new THREE.PlaneGeometry(60, 60),
  new THREE.MeshStandardMaterial({ color: 0x8d918a }));
scene.add(floor);
const grid = new THREE.GridHelper(60, 60, 0x5c5f5a, 0x777b74);
grid.rotation.x = Math.PI / 2;
grid.position.z = 0.002;
scene.add(grid);

const camera = new THREE.PerspectiveCamera(60, window.innerWidth / window.innerHeight, 0.02, 300);
camera.position.set(-3, -3, 3);
const controls = new OrbitControls(camera, renderer.domElement);
window.addEventListener('resize', () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(window.innerWidth, window.innerHeight);
});

// ---- objects ----------------------------------------------------------------------------
const objects = new Map();  // id -> { group, name }
const SHAPE_BOX = 0, SHAPE_CYLINDER = 1, KIND_RAMP = 2;

function material(color) {
  const [r, g, b, a] = color ?? [0.6, 0.6, 0.6, 1];
  return new THREE.MeshStandardMaterial({
    color: new THREE.Color(r, g, b), transparent: a < 1, opacity: a, roughness: 0.8,
  });
}

function componentMesh(c) {
  let geometry;
  if (c.shape === SHAPE_BOX) {
    geometry = new THREE.BoxGeometry(c.size[0], c.size[1], c.size[2]);
  } else if (c.shape === SHAPE_CYLINDER) {
    geometry = new THREE.CylinderGeometry(c.size[0], c.size[0], c.size[2], 24);
    geometry.rotateX(Math.PI / 2);  // three's cylinders stand along y, ours along z
  } else {
    geometry = new THREE.SphereGeometry(c.size[0], 24, 16);
  }
  const mesh = new THREE.Mesh(geometry, material(c.color));
  mesh.position.fromArray(c.position);
  mesh.quaternion.fromArray(c.orientation);
  return mesh;
}

/// A ramp with no components: a wedge of width x height rising at angle along x.
function rampMesh(ramp) {
  const [width, height, angle] = ramp;
  const depth = height / Math.tan(Math.max(angle, 0.01));
  const shape = new THREE.Shape([new THREE.Vector2(-depth / 2, 0), new THREE.Vector2(depth / 2, 0),
    new THREE.Vector2(depth / 2, height)]);
  const geometry = new THREE.ExtrudeGeometry(shape, { depth: width, bevelEnabled: false });
  geometry.rotateX(Math.PI / 2);
  geometry.translate(0, width / 2, -height / 2);
  return new THREE.Mesh(geometry, material([0.7, 0.6, 0.4, 1]));
}

function setPose(object3d, pose) {
  object3d.position.set(pose[0], pose[1], pose[2]);
  object3d.quaternion.set(pose[3], pose[4], pose[5], pose[6]);
}

function buildScene(message) {
  for (const { group } of objects.values()) {
    scene.remove(group);
    group.traverse((o) => { o.geometry?.dispose(); o.material?.dispose(); });
  }
  objects.clear();
  const list = document.getElementById('objects');
  list.replaceChildren();
  for (const o of message.objects) {
    const group = new THREE.Group();
    for (const c of o.components) group.add(componentMesh(c));
    if (o.components.length === 0 && o.kind === KIND_RAMP) group.add(rampMesh(o.ramp));
    setPose(group, o.pose);
    group.name = o.name;
    scene.add(group);
    objects.set(o.id, { group, name: o.name });
    const item = document.createElement('li');
    item.textContent = `${o.id} ${o.name}`;
    item.dataset.id = o.id;
    list.append(item);
  }
  document.getElementById('count').textContent = objects.size;
  state.domain = message.domain;
  state.robot = message.robot;
  state.objectIds = [...objects.keys()].sort((a, b) => a - b);
  needsDrawnCount = true;
  dirty = true;
}

// ---- the robot ----------------------------------------------------------------------------
const robot = new THREE.Group();
robot.visible = false;
scene.add(robot);
{
  const body = new THREE.Mesh(new THREE.BoxGeometry(0.46, 0.30, 0.16), material([0.85, 0.45, 0.1, 1]));
  body.position.z = 0.0;
  robot.add(body);
  const wheelGeometry = new THREE.CylinderGeometry(0.085, 0.085, 0.05, 20);
  for (const x of [-0.16, 0, 0.16]) {
    for (const y of [-0.19, 0.19]) {
      const wheel = new THREE.Mesh(wheelGeometry, material([0.12, 0.12, 0.12, 1]));
      wheel.position.set(x, y, -0.082);
      robot.add(wheel);
    }
  }
  const mast = new THREE.Mesh(new THREE.BoxGeometry(0.06, 0.2, 0.3), material([0.3, 0.3, 0.32, 1]));
  mast.position.set(-0.02, 0, 0.23);
  robot.add(mast);
}
const slew = new THREE.Group();    // about z through the pivot
slew.position.fromArray(KURT.pivot);
robot.add(slew);
const lift = new THREE.Group();    // about -y: positive raises the tip
slew.add(lift);
const boom = new THREE.Mesh(new THREE.BoxGeometry(KURT.boom, 0.03, 0.03), material([0.9, 0.8, 0.1, 1]));
boom.position.x = KURT.boom / 2;
lift.add(boom);
const magnet = new THREE.Mesh(new THREE.CylinderGeometry(0.04, 0.04, 0.03, 20), material([0.25, 0.25, 0.3, 1]));
magnet.geometry.rotateX(Math.PI / 2);
slew.add(magnet);  // hangs plumb below the tip, whatever the boom's angle
const cable = new THREE.Line(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]),
  new THREE.LineBasicMaterial({ color: 0x111111 }));
slew.add(cable);

function setCrane([slewAngle, liftAngle, hoist], magnetOn) {
  slew.rotation.z = slewAngle;
  lift.rotation.y = -liftAngle;
  const tip = new THREE.Vector3(KURT.boom * Math.cos(liftAngle), 0, KURT.boom * Math.sin(liftAngle));
  magnet.position.set(tip.x, 0, tip.z - KURT.magnetBelowTip - hoist + 0.015);
  magnet.material.color.set(magnetOn ? 0xd03030 : 0x404048);
  cable.geometry.setFromPoints([tip, magnet.position.clone()]);
}

// ---- laser overlays (in base_link) --------------------------------------------------------
const scanLine = new THREE.Points(new THREE.BufferGeometry(),
  new THREE.PointsMaterial({ color: 0xff2020, size: 4, sizeAttenuation: false }));
scanLine.position.z = KURT.laserZ;
robot.add(scanLine);
const cloud = new THREE.Points(new THREE.BufferGeometry(),
  new THREE.PointsMaterial({ color: 0x20c0ff, size: 2, sizeAttenuation: false }));
robot.add(cloud);
document.getElementById('show-scan').addEventListener('change', (e) => { scanLine.visible = e.target.checked; });
document.getElementById('show-cloud').addEventListener('change', (e) => { cloud.visible = e.target.checked; });

function showScan(message) {
  const points = [];
  message.ranges.forEach((r, i) => {
    if (r === null) return;
    const a = message.angle_min + i * message.angle_increment;
    points.push(r * Math.cos(a), r * Math.sin(a), 0);
  });
  scanLine.geometry.setAttribute('position', new THREE.Float32BufferAttribute(points, 3));
  state.scans += 1;
  dirty = true;
}

function showCloud(message) {
  cloud.geometry.setAttribute('position', new THREE.Float32BufferAttribute(message.points, 3));
  state.clouds += 1;
  dirty = true;
}

// ---- camera modes (the simulator's names) ------------------------------------------------
const buttons = document.querySelectorAll('#modes button');
function setMode(mode) {
  state.mode = mode;
  dirty = true;
  controls.enabled = mode === 'MouseOnly';
  for (const b of buttons) b.classList.toggle('active', b.dataset.mode === mode);
}
for (const b of buttons) b.addEventListener('click', () => setMode(b.dataset.mode));
setMode('Follow');

const up = new THREE.Vector3(0, 0, 1);
function placeCamera() {
  if (!robot.visible || state.mode === 'MouseOnly') {
    controls.update();
    return;
  }
  const at = (x, y, z) => new THREE.Vector3(x, y, z).applyMatrix4(robot.matrixWorld);
  robot.updateMatrixWorld();
  camera.up.copy(up);
  if (state.mode === 'FixedFollow') {
    camera.position.copy(robot.position).add(new THREE.Vector3(-2.2, -2.2, 2.0));
    camera.lookAt(robot.position);
  } else if (state.mode === 'Follow') {
    camera.position.copy(at(-1.8, 0, 1.3));
    camera.lookAt(at(0.8, 0, 0));
  } else if (state.mode === 'Inside') {
    camera.position.copy(at(0.0, 0, 0.5));
    camera.lookAt(at(1.0, 0, 0.35));
  } else {
    const y = state.mode === 'LeftCamera' ? KURT.camera[1] : -KURT.camera[1];
    camera.position.copy(at(KURT.camera[0], y, KURT.camera[2]));
    camera.lookAt(at(KURT.camera[0] + Math.cos(KURT.cameraPitch), y, KURT.camera[2] - Math.sin(KURT.cameraPitch)));
  }
  controls.target.copy(robot.position);
}

// ---- the connection ----------------------------------------------------------------------
const status = document.getElementById('status');
let needsDrawnCount = false;
let lastUpdate = null;
const imageUrls = {};

function applyUpdate(message) {
  state.simTime = message.time;
  state.rtf = message.rtf;
  const now = Date.now();
  for (const [id, pose] of Object.entries(message.objects)) {
    const o = objects.get(Number(id));
    if (!o) continue;
    if (state.watched.has(Number(id))) {
      const seen = (state.changes[id] ??= []);
      const last = seen[seen.length - 1];
      if (!last || last[1] !== pose[0] || last[2] !== pose[1] || last[3] !== pose[2]) {
        seen.push([now, pose[0], pose[1], pose[2]]);
      }
    }
    setPose(o.group, pose);
  }
  if (message.robot) {
    const p = message.robot.pose;
    setPose(robot, p);
    robot.visible = true;
    setCrane(message.robot.crane, message.robot.magnet);
    const yaw = Math.atan2(2 * (p[6] * p[5] + p[3] * p[4]), 1 - 2 * (p[4] * p[4] + p[5] * p[5]));
    state.robotKnown = true;
    state.robotPose = [p[0], p[1], yaw];
  }
  state.updates += 1;
  lastUpdate = message;
  dirty = true;
}

// ---- a controller's plan ------------------------------------------------------------------
const planPanel = document.getElementById('plan');
const planLabels = new THREE.Group();
scene.add(planLabels);

/// A text sprite standing over a thing: its name, label and confidence.
function labelSprite(text) {
  const canvas = document.createElement('canvas');
  canvas.width = 256;
  canvas.height = 40;
  const g = canvas.getContext('2d');
  g.fillStyle = 'rgba(20, 24, 30, 0.8)';
  g.fillRect(0, 0, canvas.width, canvas.height);
  g.fillStyle = '#fff';
  g.font = '20px sans-serif';
  g.fillText(text, 6, 27);
  const sprite = new THREE.Sprite(new THREE.SpriteMaterial({ map: new THREE.CanvasTexture(canvas), depthTest: false }));
  sprite.scale.set(0.64, 0.1, 1);
  return sprite;
}

function showPlan(message) {
  planPanel.replaceChildren();
  const head = document.createElement('div');
  head.className = 'plan-head';
  head.textContent = `plan ${message.round} for ${message.goal}`;
  planPanel.appendChild(head);
  const list = document.createElement('ol');
  message.steps.forEach((step, i) => {
    const item = document.createElement('li');
    item.className = `step ${step.status.replaceAll(' ', '-')}${i === message.current ? ' current' : ''}`;
    item.textContent = `${step.action} -> ${step.predicted} (p ${step.probability.toFixed(2)})` +
      (step.perceived ? `: ${step.perceived}` : '');
    list.appendChild(item);
  });
  planPanel.appendChild(list);
  if (message.outcome) {
    const outcome = document.createElement('div');
    outcome.className = 'plan-outcome';
    outcome.textContent = message.outcome;
    planPanel.appendChild(outcome);
  }
  for (const old of planLabels.children) old.material.map.dispose();
  planLabels.clear();
  for (const thing of message.things) {
    const sprite = labelSprite(`${thing.name}: ${thing.label} ${thing.confidence.toFixed(2)}`);
    sprite.position.set(thing.position[0], thing.position[1], 0.35);
    planLabels.add(sprite);
  }
  state.plan = {
    round: message.round, goal: message.goal, current: message.current, outcome: message.outcome,
    steps: message.steps.map((s) => [s.action, s.status]), labels: message.things.map((t) => t.name),
  };
  dirty = true;
}

function showImage(data) {
  const bytes = new Uint8Array(data);
  const eye = bytes[0] === 76 ? 'left' : 'right';  // 'L'
  const url = URL.createObjectURL(new Blob([bytes.subarray(1)], { type: 'image/jpeg' }));
  const img = document.getElementById(eye);
  img.src = url;
  if (imageUrls[eye]) URL.revokeObjectURL(imageUrls[eye]);
  imageUrls[eye] = url;
  state.images += 1;
}

function connect() {
  const socket = new WebSocket(`ws://${location.host}/ws`);
  socket.binaryType = 'arraybuffer';
  socket.onopen = () => {
    state.connected = true;
    socket.send(JSON.stringify({ type: 'hello' }));
  };
  socket.onmessage = (event) => {
    if (typeof event.data !== 'string') {
      showImage(event.data);
      return;
    }
    const message = JSON.parse(event.data);
    if (message.type === 'scene') buildScene(message);
    else if (message.type === 'update') applyUpdate(message);
    else if (message.type === 'scan') showScan(message);
    else if (message.type === 'cloud') showCloud(message);
    else if (message.type === 'plan') showPlan(message);
    else if (message.type === 'hello') state.domain = message.domain;
    else if (message.type === 'error') state.errors.push(message.message);
  };
  socket.onclose = () => {
    state.connected = false;
    setTimeout(connect, 1000);
  };
}
connect();

function describe() {
  const rtf = lastUpdate ? lastUpdate.rtf.toFixed(2) : '-';
  const where = state.robotPose ? state.robotPose.map((v) => v.toFixed(2)).join(', ') : '-';
  status.textContent = `${state.connected ? 'connected' : 'connecting ...'}   domain ${state.domain ?? '-'}\n` +
    `sim time ${state.simTime.toFixed(2)} s   rtf ${rtf}\n` +
    `${state.robot ?? 'robot'} x, y, yaw: ${where}\n` +
    `${objects.size} objects, ${state.scans} scans, ${state.clouds} clouds`;
}

controls.addEventListener('change', () => { dirty = true; });
window.addEventListener('resize', () => { dirty = true; });
renderer.setAnimationLoop(() => {
  if (!dirty) return;
  dirty = false;
  placeCamera();
  renderer.render(scene, camera);
  if (needsDrawnCount) {
    // The objects are in the picture now: say how many (tests wait for this).
    state.drawn = objects.size;
    document.title = `macsim_web: ${state.drawn} objects drawn (domain ${state.domain})`;
    needsDrawnCount = false;
  }
  describe();
});
