// kinema viewer: every number comes from the server (the kinema library);
// the page draws. Modules: state.js (what the page knows), api.js (HTTP and
// the pose WebSocket), scene.js (renderer, camera, controls), robot.js (link
// shapes placed by FK), world.js (scene obstacles, collisions and the
// minimum distance), panels.js (joints, FK readout, IK), player.js, plan.js
// (the Plan button).
import * as THREE from 'three';
import { $, state, setStatus, dist3 } from './state.js';
import { api, PoseLink, latestOnly } from './api.js';
import { View } from './scene.js';
import { RobotModel, COLLIDING } from './robot.js';
import { World } from './world.js';
import { Gizmo } from './gizmo.js';
import { CellPlayer } from './cell.js';
import { PointCloud } from './points.js';
import { bindPanels, buildJointPanel, setQ, showFk, fillIkFromTool, ikTargetFromInputs } from './panels.js';
import { bindPlan } from './plan.js';
import { bindPlayer, resetPlayer, stopPlayer, playTrajectory } from './player.js';
import { Follower } from './follow.js';

// Errors the page met (uncaught ones and console.error), for the tests to read.
const errors = [];
window.addEventListener('error', (e) => errors.push(String(e.message || e)));
window.addEventListener('unhandledrejection', (e) => errors.push(String(e.reason)));
const consoleError = console.error.bind(console);
console.error = (...args) => { errors.push(args.map(String).join(' ')); consoleError(...args); };

const view = new View($('view'));
const robot = new RobotModel(view);
const world = new World(view);
const gizmo = new Gizmo(view);
const cell = new CellPlayer(view);
const cloud = new PointCloud(view);
const poses = new PoseLink(applyFk, (e) => setStatus(String(e), true));
const follower = new Follower(showAsked, (e) => setStatus(String(e), true));

function redraw() {
  robot.showFrames($('show-frames').checked);
  robot.showCollision($('show-collision').checked);
  robot.setTarget(state.ikTarget);
  robot.setEllipsoid($('show-ellipsoid').checked ? state.manip : null, parseFloat($('ellipsoid-scale').value) * state.reach);
  view.requestRender();
}

function applyFk(fk) {
  if (!state.robot || fk.robot !== state.robot.name) return;
  state.fk = fk;
  robot.setPose(fk);
  gizmo.place(fk.T);
  showFk(fk);
  if ($('show-collide').checked) checkCollisions({ robot: fk.robot, q: fk.q });
  if ($('show-ellipsoid').checked) fetchManip(fk.q); else redraw();
}

// The server's collision check at a configuration (the robot's collision
// shapes against themselves and the server's scene): the bodies of every
// colliding pair in red, the closest pair's segment and distance.
const checkCollisions = latestOnly(async (req) => {
  const res = await api('/api/collide', req);
  // An answer for another robot, or arriving after the check was turned off, is not shown.
  if (!state.robot || req.robot !== state.robot.name || !$('show-collide').checked) return;
  state.collide = res.ok ? res.data : null;
  showCollisions(res.ok ? res.data : null, res.ok ? '' : res.data.error);
}, (e) => setStatus(String(e), true));

function showCollisions(c, error) {
  const bodies = new Set();
  if (c) for (const p of c.pairs) { bodies.add(p.a); bodies.add(p.b); }
  robot.highlight(bodies);
  world.highlight(bodies);
  const d = c && c.min_distance;
  world.setSegment(d, 0.006 * state.reach);
  const out = $('collide-readout');
  if (!c) { out.textContent = error || ''; out.className = 'message'; view.requestRender(); return; }
  const pairs = c.pairs.map((p) => `${p.a} – ${p.b}`).join('\n  ');
  out.textContent = (c.collision ? `COLLISION:\n  ${pairs}\n` : 'no collision\n') +
    (d ? `min distance ${(d.distance * 1000).toFixed(6)} mm\n  ${d.a} – ${d.b}` : 'no pair checked');
  out.className = c.collision ? 'message' : 'message ok';
  view.requestRender();
}

async function fetchManip(q) {
  const res = await api('/api/manip', { robot: state.robot.name, q });
  if (!res.ok) { setStatus(res.data.error, true); return; }
  state.manip = res.data;
  const m = res.data, e = m.ellipsoid_translation;
  $('manip-readout').textContent =
    `Yoshikawa      ${m.yoshikawa.toExponential(4)}\n` +
    `translational  ${m.yoshikawa_translation.toExponential(4)}\n` +
    `condition      ${m.condition === null ? '∞ (singular)' : m.condition.toFixed(2)}\n` +
    `rank           ${m.rank}\n` +
    `radii [m/s per rad/s]\n  ${e.radii.map((x) => x.toFixed(4)).join('  ')}`;
  redraw();
}

async function loadRobot(name) {
  stopPlayer();
  const [info, shapes] = await Promise.all([
    api(`/api/robots/${encodeURIComponent(name)}`),
    api(`/api/robots/${encodeURIComponent(name)}/geometry`),
  ]);
  if (!info.ok) { setStatus(info.data.error, true); return; }
  if (!shapes.ok) { setStatus(shapes.data.error, true); return; }
  const r = info.data;
  state.robot = r; state.geometry = shapes.data;
  gizmo.release();
  state.q = r.home.slice();
  state.manip = null; state.q3Anchor = null; state.ikTarget = null; state.fk = null; state.collide = null;
  showCollisions(null, '');
  const summary = state.robots.find((x) => x.name === name);
  $('robot-description').textContent = summary ? summary.description : '';
  buildJointPanel(r);
  resetPlayer(r);
  // The robot's size from its home configuration frames the view.
  const fk = await api('/api/fk', { robot: r.name, q: state.q });
  if (!fk.ok) { setStatus(fk.data.error, true); return; }
  const pts = fk.data.frames.map((f) => f.position);
  let reach = 0;
  for (let i = 1; i < pts.length; i++) reach += dist3(pts[i], pts[i - 1]);
  state.reach = Math.max(reach, 0.2);
  view.frame(state.reach);
  robot.load(shapes.data, state.reach);
  applyFk(fk.data);
  fillIkFromTool();
  const drawn = shapes.data.visual.length ? 'visual meshes' : shapes.data.collision.length ? 'collision shapes' : 'link frames only';
  setStatus(`${r.name}: ${r.dof} joints, ${drawn}`);
}

// A configuration or trajectory a program asked for (/api/view), on its robot.
async function showAsked(v) {
  if (!state.robot || state.robot.name !== v.robot) {
    $('robot-select').value = v.robot;
    await loadRobot(v.robot);
  }
  if (cell.loaded && $('cell-show').checked) showCell(false);
  if (v.t) { playTrajectory({ t: v.t, q: v.q, source: 'program request' }); return; }
  stopPlayer();
  setQ(v.q);
}

// The cell's robots instead of the robot of the panels, or the other way round.
function showCell(on) {
  $('cell-show').checked = on;
  cell.setVisible(on);
  robot.root.visible = !on;
  // The collision check is the panels' robot's: off while it is hidden.
  if ($('show-collide').checked === on) { $('show-collide').checked = !on; $('show-collide').dispatchEvent(new Event('change')); }
  view.requestRender();
}

function bindView() {
  $('reset-view').addEventListener('click', () => view.resetCamera(state.reach));
  for (const id of ['show-frames', 'show-collision']) $(id).addEventListener('change', redraw);
  // Moving the joints otherwise lets the handle go back to the tool.
  for (const id of ['sliders', 'poses']) $(id).addEventListener('input', () => gizmo.release());
  $('poses').addEventListener('click', () => gizmo.release());
  $('points-file').addEventListener('change', async () => {
    const file = $('points-file').files[0];
    if (!file) { cloud.clear(); return; }
    try {
      const s = cloud.load(await file.text(), state.reach);
      setStatus(`${file.name}: ${s.count} points` + (s.valued ? `, values ${s.min} (blue) to ${s.max} (red)` : ''));
    } catch (e) { setStatus(String(e.message || e), true); }
  });
  $('gizmo-on').addEventListener('change', () => gizmo.enable($('gizmo-on').checked));
  $('gizmo-mode').addEventListener('change', () => gizmo.setMode($('gizmo-mode').value));
  $('show-collide').addEventListener('change', () => {
    if ($('show-collide').checked && state.fk) checkCollisions({ robot: state.robot.name, q: state.fk.q });
    else { state.collide = null; showCollisions(null, ''); }
  });
  $('ellipsoid-scale').addEventListener('input', redraw);
  $('show-ellipsoid').addEventListener('change', () => {
    $('manip-readout').hidden = !$('show-ellipsoid').checked;
    if ($('show-ellipsoid').checked) fetchManip(state.q.slice()); else redraw();
  });
  $('screenshot').addEventListener('click', () => {
    const a = document.createElement('a');
    a.href = view.screenshot();
    a.download = `kinema-${state.robot ? state.robot.name : 'view'}.png`;
    a.click();
  });
}

async function init() {
  const list = await api('/api/robots');
  if (!list.ok) { setStatus(list.data.error, true); return; }
  state.robots = list.data;
  const sel = $('robot-select');
  for (const r of state.robots) {
    const o = document.createElement('option');
    o.value = r.name; o.textContent = `${r.name} (${r.dof})`;
    sel.appendChild(o);
  }
  const def = state.robots.find((r) => r.default) || state.robots[0];
  sel.value = def.name;
  sel.addEventListener('change', () => loadRobot(sel.value));
  bindPanels({ requestPose: (q) => poses.request(state.robot.name, q), redraw });
  bindPlayer();
  bindPlan(() => {
    if ($('gizmo-on').checked) return { pose: gizmo.target() };
    const t = ikTargetFromInputs();
    return t && { pose: [...t.position, ...t.rpy] };
  });
  bindView();
  const scene = await api('/api/scene');
  if (!scene.ok) { setStatus(scene.data.error, true); return; }
  world.load(scene.data);
  state.obstacles = scene.data.obstacles.length;
  await loadRobot(def.name);
  const played = await api('/api/cell');
  if (!played.ok) { setStatus(played.data.error, true); return; }
  cell.load(played.data, state.reach);
  if (cell.loaded) {
    showCell(true);
    // The camera takes in every robot of the cell over its motion, and the obstacles.
    view.frameBox(cell.box().union(new THREE.Box3().setFromObject(world.root)), state.reach);
  }
  $('cell-show').addEventListener('change', () => showCell($('cell-show').checked));
  follower.start(250);
  document.body.dataset.ready = '1';
}

// What tests (and the browser console) may read and ask.
window.kinemaViewer = {
  state,
  errors,
  get q() { return state.q.slice(); },
  get context() { return view.contextKind; },
  // Whether WebGL runs on the CPU (then without multisampling).
  get software() { return view.software; },
  get frames() { return view.frames; },
  get frameTimes() { return view.frameTimes.slice(); },
  get live() { return poses.live; },
  // The last /api/collide answer shown (null while none).
  get collide() { return state.collide; },
  // The tool gizmo: {target (T rows), pending, reached, closest, message} of its last IK request.
  get gizmo() { return gizmo.status; },
  // The gizmo's centre [m] and its drawn size [m per gizmo unit], to aim at its arrows and rings.
  get gizmoCentre() { return gizmo.centre; },
  get gizmoScale() { return gizmo.drawnScale; },
  // The last plan: {pending, ok, message, goal}, or null.
  get plan() { return state.plan; },
  // The player: {playing, time, end}, or null without a trajectory.
  get player() {
    const tr = state.traj;
    return tr && { playing: state.playing, time: state.playTime, end: tr.t[tr.t.length - 1], source: tr.source };
  },
  // The version of the last /api/view request shown (0 while none).
  get followed() { return follower.version; },
  // The cell's timeline: {sample, samples, time, playing, members: [{name, q}]}, or null.
  get cell() { return cell.status; },
  // The point cloud layer: {count, valued, min, max}, or null.
  get points() { return cloud.summary; },
  // The bodies drawn red (links and obstacles, by name), each once.
  get red() {
    const red = [...robot.drawn, ...world.obstacles].filter((m) => m.material === COLLIDING);
    return [...new Set(red.map((m) => m.userData.body))];
  },
  // Window CSS pixels [x, y] (and depth) of world point p [m].
  project: (p) => view.project(p),
  setQ: (q) => setQ(q),
  // Draws the view again at the next animation frame.
  redraw: () => view.requestRender(),
  measure: (count) => view.measure(count),
  screenshot: () => view.screenshot(),
};

init().catch((e) => { setStatus(String(e), true); errors.push(String(e)); });
