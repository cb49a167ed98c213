// The page of `semap view`: the map in 3D (three.js), fed over a WebSocket by the semap process that serves
// this page. Messages (see tools/view/view_model.h): JSON text "hello", "status", "stats", "poses", "reset";
// binary "SMV1" meshes (the whole current mesh each time).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { FlyControls } from 'three/addons/controls/FlyControls.js';

const BACKGROUND = 0x1e2230;  // the page's background; the screenshot test counts pixels that differ from it
const ERROR_MAX_M = 1.0;      // error colour ramp: 0 m green … ERROR_MAX_M and beyond red

const $ = (id) => document.getElementById(id);

// ---- scene -------------------------------------------------------------------------------------------------
const container = $('view');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setSize(window.innerWidth, window.innerHeight);
renderer.setClearColor(BACKGROUND);
container.appendChild(renderer.domElement);

const scene = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(55, window.innerWidth / window.innerHeight, 0.05, 5000);
camera.position.set(20, 20, 20);
scene.add(new THREE.HemisphereLight(0xffffff, 0x9a9aa8, 2.4));
const sun = new THREE.DirectionalLight(0xffffff, 1.0);
scene.add(sun);

const material = new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide });
let meshObject = null;       // THREE.Mesh of the current map
let meshData = null;         // the decoded arrays of the last mesh message
let up = new THREE.Vector3(0, 0, 1);
let upFixed = false;         // the server named the up axis, or it was taken from the cameras or the first mesh
let upFromCameras = false;   // taken from the camera poses (better than a guess from a small first mesh)
let upName = 'auto';
let hello = null;
const palette = new Map();   // label id -> {name, rgb}

const trajectory = { points: [], line: null, marker: null };
const stats = [];            // [frame_id, elapsed_s, fps, triangles, vertices]

// ---- navigation --------------------------------------------------------------------------------------------
let orbit = null;
let fly = null;
let nav = 'orbit';
const clock = new THREE.Clock();

function makeControls() {
  // OrbitControls takes the camera's up vector when it is made: remade when the up axis is known.
  const target = orbit ? orbit.target.clone() : new THREE.Vector3();
  if (orbit) orbit.dispose();
  if (fly) fly.dispose();
  camera.up.copy(up);
  orbit = new OrbitControls(camera, renderer.domElement);
  orbit.target.copy(target);
  orbit.enableDamping = true;
  orbit.dampingFactor = 0.12;
  orbit.screenSpacePanning = true;
  orbit.addEventListener('start', () => { autoFit = false; });
  // While following, the view keeps where the user turned it to, relative to the followed camera.
  orbit.addEventListener('end', () => {
    if ($('follow').checked) followOffset = camera.position.clone().sub(orbit.target);
  });
  fly = new FlyControls(camera, renderer.domElement);
  fly.dragToLook = true;
  fly.rollSpeed = 0.6;
  fly.movementSpeed = 10;
  setNav(nav);
}
renderer.domElement.addEventListener('pointerdown', () => { if (nav === 'fly') autoFit = false; });

function setNav(mode) {
  nav = mode;
  orbit.enabled = mode === 'orbit';
  fly.enabled = mode === 'fly';
  if (mode === 'orbit') {
    // Orbit about the point the camera looks at, at the distance it had.
    const dir = new THREE.Vector3();
    camera.getWorldDirection(dir);
    const dist = Math.max(1, camera.position.distanceTo(orbit.target));
    orbit.target.copy(camera.position).addScaledVector(dir, dist);
    camera.up.copy(up);
    orbit.update();
  }
}

function sceneBox() {
  const box = new THREE.Box3();
  if (meshObject) box.expandByObject(meshObject);
  for (const p of trajectory.points) box.expandByPoint(p.position);
  return box;
}

// Shows the whole map (and trajectory): looking 50° down from the side of its longer horizontal axis that
// the camera is on (a street runs across the screen), at the distance where the bounding box just fits.
function fitToView() {
  const box = sceneBox();
  if (box.isEmpty()) return;
  const center = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3());
  const axes = [new THREE.Vector3(1, 0, 0), new THREE.Vector3(0, 1, 0), new THREE.Vector3(0, 0, 1)]
    .filter((a) => Math.abs(a.dot(up)) < 0.5);
  const long = Math.abs(size.dot(axes[0])) >= Math.abs(size.dot(axes[1])) ? axes[0] : axes[1];
  const side = new THREE.Vector3().crossVectors(up, long).normalize();
  if (camera.position.clone().sub(center).dot(side) < 0) side.negate();
  const elevation = THREE.MathUtils.degToRad(50);
  const viewDir = side.multiplyScalar(-Math.cos(elevation)).addScaledVector(up, -Math.sin(elevation));
  camera.up.copy(up);
  camera.position.copy(center).sub(viewDir);
  camera.lookAt(center);
  camera.updateMatrixWorld();
  const right = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 0);
  const camUp = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 1);
  const tanV = Math.tan(THREE.MathUtils.degToRad(camera.fov / 2));
  const tanH = tanV * camera.aspect;
  // A corner p (relative to the centre) is seen when |p·right| <= (d + p·forward) tanH, and likewise upward.
  let distance = 1;
  for (let i = 0; i < 8; ++i) {
    const p = new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
                                i & 4 ? box.max.z : box.min.z).sub(center);
    const f = p.dot(viewDir);
    distance = Math.max(distance, Math.abs(p.dot(right)) / tanH - f, Math.abs(p.dot(camUp)) / tanV - f);
  }
  distance *= 1.08;
  const radius = size.length() / 2;
  camera.position.copy(center).addScaledVector(viewDir, -distance);
  camera.lookAt(center);
  orbit.target.copy(center);
  camera.near = Math.max(0.05, distance / 2000);
  camera.far = distance * 20 + radius * 4;
  camera.updateProjectionMatrix();
  fly.movementSpeed = Math.max(2, radius / 5);
  orbit.update();
  sun.position.copy(center).addScaledVector(up, radius * 3).addScaledVector(right, radius);
}

// ---- follow the camera -------------------------------------------------------------------------------------
let followOffset = null;  // viewer camera position minus the followed camera's position
let autoFit = true;       // fit every new mesh to the view until the user moves the view or follows

function follow() {
  if (!$('follow').checked || trajectory.points.length === 0) return;
  const last = trajectory.points[trajectory.points.length - 1];
  if (!followOffset) {
    // Behind and above the vehicle's camera (KITTI cameras look along +z), unless the user moved since.
    const forward = new THREE.Vector3(0, 0, 1).applyQuaternion(last.quaternion);
    forward.addScaledVector(up, -forward.dot(up)).normalize();
    followOffset = forward.multiplyScalar(-12).addScaledVector(up, 4);  // a chase view, under any lid
  }
  if (nav === 'orbit') {
    orbit.target.copy(last.position);
    camera.position.copy(last.position).add(followOffset);
    orbit.update();
  }
}

$('follow').addEventListener('change', () => {
  followOffset = null;
  autoFit = false;
  if ($('follow').checked && nav !== 'orbit') { $('nav').value = 'orbit'; setNav('orbit'); }
  follow();
});

// ---- the mesh ----------------------------------------------------------------------------------------------
function decodeMesh(buffer) {
  const view = new DataView(buffer);
  const magic = String.fromCharCode(view.getUint8(0), view.getUint8(1), view.getUint8(2), view.getUint8(3));
  if (magic !== 'SMV1') throw new Error(`not a semap mesh message (${magic})`);
  const n = view.getUint32(4, true);
  const m = view.getUint32(8, true);
  const flags = view.getUint32(12, true);
  const frameId = Number(view.getBigInt64(16, true));
  let offset = 24;
  const positions = new Float32Array(buffer, offset, 3 * n); offset += 12 * n;
  let error = null;
  if (flags & 1) { error = new Float32Array(buffer, offset, n); offset += 4 * n; }
  const indices = new Uint32Array(buffer, offset, 3 * m); offset += 12 * m;
  const colours = new Uint8Array(buffer, offset, 3 * n); offset += 3 * n;
  const labels = new Uint8Array(buffer, offset, n);
  return { n, m, frameId, positions, error, indices, colours, labels };
}

// The mesh's thinnest bounding-box axis as up, y taken as down (KITTI odometry, camera frames), as
// `semap render --up auto` does.
function guessUp(positions) {
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < positions.length; i += 3) {
    for (let k = 0; k < 3; ++k) {
      const v = positions[i + k];
      if (v < lo[k]) lo[k] = v;
      if (v > hi[k]) hi[k] = v;
    }
  }
  const extent = [0, 1, 2].map((k) => hi[k] - lo[k]);
  const axis = extent.indexOf(Math.min(...extent));
  const v = new THREE.Vector3();
  v.setComponent(axis, axis === 1 ? -1 : 1);
  return v;
}

// The cameras' mean up direction (KITTI cameras: y down, so up is -y of the camera frame, turned into the
// world), snapped to the nearest axis when within 10° of it.
function upOfCameras(points) {
  const sum = new THREE.Vector3();
  for (const p of points) sum.add(new THREE.Vector3(0, -1, 0).applyQuaternion(p.quaternion));
  if (sum.lengthSq() === 0) return null;
  sum.normalize();
  for (let k = 0; k < 3; ++k) {
    if (Math.abs(sum.getComponent(k)) > Math.cos(THREE.MathUtils.degToRad(10))) {
      const axis = new THREE.Vector3();
      axis.setComponent(k, Math.sign(sum.getComponent(k)));
      return axis;
    }
  }
  return sum;
}

function upFromName(name) {
  const v = new THREE.Vector3();
  v.setComponent('xyz'.indexOf(name[name.length - 1]), name[0] === '-' ? -1 : 1);
  return v;
}

function ramp(t) {  // 0 green, 0.5 yellow, 1 red
  t = Math.min(1, Math.max(0, t));
  return t < 0.5 ? [2 * t, 0.8, 0.2] : [1, 0.8 * (2 - 2 * t), 0.2];
}

function heightRange(d) {
  const h = new Float32Array(d.n);
  for (let i = 0; i < d.n; ++i) {
    h[i] = d.positions[3 * i] * up.x + d.positions[3 * i + 1] * up.y + d.positions[3 * i + 2] * up.z;
  }
  const sorted = Float32Array.from(h).sort();
  const lo = sorted[Math.floor(0.02 * (sorted.length - 1))] ?? 0;
  const hi = sorted[Math.floor(0.98 * (sorted.length - 1))] ?? 1;
  return { h, lo, hi: hi > lo ? hi : lo + 1 };
}

function vertexColours(d, mode) {
  const c = new Float32Array(3 * d.n);
  if (mode === 'label') {
    for (let i = 0; i < d.n; ++i) {
      const entry = palette.get(d.labels[i]);
      const rgb = entry ? entry.rgb : [0, 0, 0];
      for (let k = 0; k < 3; ++k) c[3 * i + k] = rgb[k] / 255;
    }
  } else if (mode === 'error' && d.error) {
    for (let i = 0; i < d.n; ++i) c.set(ramp(d.error[i] / ERROR_MAX_M), 3 * i);
  } else if (mode === 'height') {
    const { h, lo, hi } = heightRange(d);
    for (let i = 0; i < d.n; ++i) c.set(ramp((h[i] - lo) / (hi - lo)), 3 * i);
  } else {
    for (let i = 0; i < 3 * d.n; ++i) c[i] = d.colours[i] / 255;
  }
  // Colours are sRGB: three.js lights in linear space.
  const col = new THREE.Color();
  for (let i = 0; i < d.n; ++i) {
    col.setRGB(c[3 * i], c[3 * i + 1], c[3 * i + 2], THREE.SRGBColorSpace);
    c[3 * i] = col.r; c[3 * i + 1] = col.g; c[3 * i + 2] = col.b;
  }
  return c;
}

function showMesh(d) {
  const first = meshObject === null;
  if (!upFixed && d.n > 0) {
    up = upName === 'auto' ? guessUp(d.positions) : upFromName(upName);
    upFixed = true;
    makeControls();
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(d.positions, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(vertexColours(d, $('colour').value), 3));
  geometry.setIndex(new THREE.BufferAttribute(d.indices, 1));
  geometry.computeVertexNormals();
  geometry.computeBoundingSphere();
  if (meshObject) {
    meshObject.geometry.dispose();
    meshObject.geometry = geometry;
  } else {
    meshObject = new THREE.Mesh(geometry, material);
    scene.add(meshObject);
  }
  meshData = d;
  // What the page draws: the test compares it with the run's mesh file.
  const triangles = geometry.index.count / 3;
  $('triangles').textContent = triangles.toLocaleString('en-US').replace(/,/g, '\u2009');
  $('triangles').dataset.count = String(triangles);
  $('vertices').textContent = d.n.toLocaleString('en-US').replace(/,/g, '\u2009');
  if (d.frameId >= 0) $('frame').textContent = String(d.frameId);
  if ((first || autoFit) && d.n > 0 && !$('follow').checked) fitToView();
  updateLegend();
  window.semapView.meshesShown += 1;
}

function recolour() {
  if (!meshObject || !meshData) return;
  meshObject.geometry.setAttribute('color', new THREE.BufferAttribute(vertexColours(meshData, $('colour').value), 3));
  updateLegend();
}

function updateLegend() {
  const legend = $('legend');
  const mode = $('colour').value;
  legend.replaceChildren();
  if (!meshData) return;
  if (mode === 'label') {
    const counts = new Map();
    for (const l of meshData.labels) counts.set(l, (counts.get(l) || 0) + 1);
    const title = document.createElement('div');
    title.textContent = `classes (${hello?.class_scheme || 'labels'}), by share of vertices`;
    title.className = 'label';
    legend.appendChild(title);
    for (const [id, count] of [...counts].sort((a, b) => b[1] - a[1])) {
      const entry = palette.get(id) || { name: `label ${id}`, rgb: [0, 0, 0] };
      const row = document.createElement('div');
      const swatch = document.createElement('span');
      swatch.className = 'swatch';
      swatch.style.background = `rgb(${entry.rgb.join(',')})`;
      row.appendChild(swatch);
      row.appendChild(document.createTextNode(`${entry.name} ${(100 * count / meshData.n).toFixed(1)} %`));
      legend.appendChild(row);
    }
  } else if (mode === 'error' || mode === 'height') {
    const title = document.createElement('div');
    title.className = 'label';
    let lo = '0 m', hi = `≥ ${ERROR_MAX_M} m`;
    if (mode === 'error') {
      title.textContent = `distance to the true surface (${hello?.error_source || ''})`;
    } else {
      const r = heightRange(meshData);
      title.textContent = 'height along the up axis';
      lo = `${r.lo.toFixed(1)} m`; hi = `${r.hi.toFixed(1)} m`;
    }
    legend.appendChild(title);
    const bar = document.createElement('canvas');
    bar.width = 160; bar.height = 12; bar.className = 'ramp';
    const ctx = bar.getContext('2d');
    for (let x = 0; x < 160; ++x) {
      const [r, g, b] = ramp(x / 159);
      ctx.fillStyle = `rgb(${r * 255},${g * 255},${b * 255})`;
      ctx.fillRect(x, 0, 1, 12);
    }
    legend.appendChild(bar);
    const ends = document.createElement('div');
    ends.className = 'label';
    ends.textContent = `${lo} … ${hi}`;
    legend.appendChild(ends);
  }
}

$('colour').addEventListener('change', recolour);
$('wireframe').addEventListener('change', () => { material.wireframe = $('wireframe').checked; });
$('nav').addEventListener('change', () => setNav($('nav').value));
$('fit').addEventListener('click', () => { $('follow').checked = false; autoFit = true; fitToView(); });
$('show-trajectory').addEventListener('change', () => {
  const on = $('show-trajectory').checked;
  if (trajectory.line) trajectory.line.visible = on;
  if (trajectory.marker) trajectory.marker.visible = on;
});
$('snapshot').addEventListener('click', () => {
  renderer.domElement.toBlob((blob) => {
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = 'semap-view.png';
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 1000);
  }, 'image/png');
});
window.addEventListener('keydown', (e) => {
  if (e.key === 'Home') { $('follow').checked = false; autoFit = true; fitToView(); }
});

// ---- trajectory --------------------------------------------------------------------------------------------
function cameraMarker(size) {
  // A frustum: the camera centre and its image plane at `size` metres (KITTI: x right, y down, z forward).
  const w = size * 0.8, h = size * 0.3, z = size;
  const c = [[-w, -h, z], [w, -h, z], [w, h, z], [-w, h, z]];
  const pts = [];
  for (let i = 0; i < 4; ++i) {
    pts.push(0, 0, 0, ...c[i]);
    pts.push(...c[i], ...c[(i + 1) % 4]);
  }
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(pts, 3));
  return new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: 0xff4fd8 }));
}

function addPoses(points) {
  for (const [frameId, x, y, z, qw, qx, qy, qz] of points) {
    trajectory.points.push({
      frameId,
      position: new THREE.Vector3(x, y, z),
      quaternion: new THREE.Quaternion(qx, qy, qz, qw),
    });
  }
  if (upName === 'auto' && !upFromCameras) {
    const camerasUp = upOfCameras(trajectory.points);
    if (camerasUp) {
      up = camerasUp;
      upFixed = upFromCameras = true;
      makeControls();
      if (meshObject && autoFit) fitToView();
    }
  }
  if (trajectory.line) { scene.remove(trajectory.line); trajectory.line.geometry.dispose(); }
  const g = new THREE.BufferGeometry().setFromPoints(trajectory.points.map((p) => p.position));
  trajectory.line = new THREE.Line(g, new THREE.LineBasicMaterial({ color: 0xffd34f }));
  trajectory.line.visible = $('show-trajectory').checked;
  scene.add(trajectory.line);
  if (!trajectory.marker) {
    trajectory.marker = cameraMarker(2.0);
    scene.add(trajectory.marker);
  }
  const last = trajectory.points[trajectory.points.length - 1];
  trajectory.marker.position.copy(last.position);
  trajectory.marker.quaternion.copy(last.quaternion);
  trajectory.marker.visible = $('show-trajectory').checked;
  follow();
}

// ---- statistics --------------------------------------------------------------------------------------------
// A small chart of one or more series over frames, each scaled to its own maximum (named at the top left).
function spark(canvas, series, format) {
  const ctx = canvas.getContext('2d');
  const W = canvas.width, H = canvas.height;
  ctx.clearRect(0, 0, W, H);
  ctx.font = '20px system-ui, sans-serif';
  let labelX = 6;
  for (const { values, colour, name } of series) {
    if (values.length === 0) continue;
    const max = Math.max(...values, 1e-9);
    ctx.strokeStyle = colour;
    ctx.lineWidth = 3;
    ctx.beginPath();
    values.forEach((v, i) => {
      const x = values.length === 1 ? W / 2 : (i / (values.length - 1)) * (W - 4) + 2;
      const y = H - 4 - (v / max) * (H - 26);
      if (i === 0) ctx.moveTo(x, y); else ctx.lineTo(x, y);
    });
    ctx.stroke();
    ctx.fillStyle = colour;
    const text = `${name} ${format(max)}`;
    ctx.fillText(text, labelX, 20);
    labelX += ctx.measureText(text).width + 16;
  }
}

function addStats(points) {
  stats.push(...points);
  const last = stats[stats.length - 1];
  $('fps').textContent = `${last[2].toFixed(2)} f/s`;
  if (!meshData || meshData.frameId < 0) $('frame').textContent = String(last[0]);
  const count = (v) => Math.round(v).toLocaleString('en-US');
  spark($('spark-fps'), [{ values: stats.map((s) => s[2]), colour: '#6fd0ff', name: 'max' }], (v) => v.toFixed(1));
  spark($('spark-size'), [{ values: stats.map((s) => s[3]), colour: '#9dff7a', name: 'triangles' },
                          { values: stats.map((s) => s[4]), colour: '#ffb86b', name: 'map vertices' }], count);
}

function reset() {
  // A new run on the same channels.
  if (meshObject) { scene.remove(meshObject); meshObject.geometry.dispose(); meshObject = null; }
  meshData = null;
  if (trajectory.line) { scene.remove(trajectory.line); trajectory.line = null; }
  if (trajectory.marker) { scene.remove(trajectory.marker); trajectory.marker = null; }
  trajectory.points = [];
  stats.length = 0;
  upFixed = upName !== 'auto';
  upFromCameras = false;
  autoFit = !$('follow').checked;
  $('triangles').textContent = '0';
  $('triangles').dataset.count = '0';
  $('vertices').textContent = '0';
  $('frame').textContent = '–';
  $('fps').textContent = '–';
  spark($('spark-fps'), [], String);
  spark($('spark-size'), [], String);
  updateLegend();
}

// ---- connection --------------------------------------------------------------------------------------------
window.semapView = {
  meshesShown: 0, framesDrawn: 0, connected: false, hello: null,
  camera: () => ({ position: camera.position.toArray(), target: orbit.target.toArray(), up: up.toArray() }),
};

function onHello(h) {
  hello = h;
  window.semapView.hello = h;
  $('source').textContent = `${h.kind}: ${h.name}`;
  palette.clear();
  for (const c of h.palette) palette.set(c.id, { name: c.name, rgb: c.rgb });
  const errorOption = $('colour').querySelector('option[value=error]');
  errorOption.disabled = !h.has_error;
  errorOption.textContent = h.has_error ? 'error (distance to the true surface)' : 'error (needs a true surface)';
  upName = h.up || 'auto';
  if (upName !== 'auto') {
    up = upFromName(upName);
    upFixed = true;
    makeControls();
  }
  // The page's address may preset the view: ?colour=label|error|height|image&follow=1&trajectory=0
  const params = new URLSearchParams(location.search);
  if (params.get('follow') === '1') { $('follow').checked = true; autoFit = false; }
  if (params.get('trajectory') === '0') $('show-trajectory').checked = false;
  const wanted = params.get('colour');
  if (wanted && !$('colour').querySelector(`option[value=${wanted}]`)?.disabled) {
    $('colour').value = wanted;
    recolour();
  }
}

function connect() {
  const ws = new WebSocket(`${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`);
  ws.binaryType = 'arraybuffer';
  ws.onopen = () => { window.semapView.connected = true; };
  ws.onmessage = (event) => {
    if (event.data instanceof ArrayBuffer) {
      showMesh(decodeMesh(event.data));
      return;
    }
    const msg = JSON.parse(event.data);
    if (msg.type === 'hello') onHello(msg);
    else if (msg.type === 'status') $('status').textContent = msg.text;
    else if (msg.type === 'stats') addStats(msg.points);
    else if (msg.type === 'poses') addPoses(msg.points);
    else if (msg.type === 'reset') reset();
  };
  ws.onclose = () => {
    window.semapView.connected = false;
    $('status').textContent = 'disconnected from semap view; retrying…';
    setTimeout(connect, 1000);
  };
}

// ---- main loop ---------------------------------------------------------------------------------------------
window.addEventListener('resize', () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(window.innerWidth, window.innerHeight);
});

makeControls();
renderer.setAnimationLoop(() => {
  const dt = clock.getDelta();
  if (nav === 'fly') fly.update(dt); else orbit.update();
  renderer.render(scene, camera);
  window.semapView.framesDrawn += 1;
});
connect();
