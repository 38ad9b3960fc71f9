// kinema viewer: every number comes from the server's JSON API (the kinema
// library); this file only draws. The 3D view is a 2D canvas with a
// perspective projection of its own: an orbit camera around a target point,
// primitives sorted far to near (painter's algorithm).
'use strict';

const $ = (id) => document.getElementById(id);
const DEG = 180 / Math.PI;

const state = {
  robots: [],
  robot: null,        // GET /api/robots/{name}
  q: [],
  fk: null,           // last POST /api/fk answer
  manip: null,        // last POST /api/manip answer
  reach: 1,
  camera: { yaw: -0.9, pitch: 0.45, dist: 3, target: [0, 0, 0.4] },
  ikTarget: null,     // pose of the last IK request (T rows)
  q3Anchor: null,     // tool pose kept while the q3 slider moves
  traj: null,         // { t: [], q: [[]], source }
  playing: false,
  playTime: 0,
};

// ---------------------------------------------------------------- API ----

async function api(path, body) {
  const init = body === undefined ? {} : {
    method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body),
  };
  const res = await fetch(path, init);
  let data = null;
  try { data = await res.json(); } catch (e) { data = { error: `${path}: the answer is not JSON (${res.status})` }; }
  return { ok: res.ok, status: res.status, data };
}

// Runs `fn(arg)` with at most one call in flight; while one runs, only the
// latest argument is kept and sent next (sliders stay smooth, nothing queues up).
function latestOnly(fn) {
  let busy = false, pending = null, has = false;
  const go = async (arg) => {
    busy = true;
    try { await fn(arg); } catch (e) { setStatus(String(e), true); }
    busy = false;
    if (has) { has = false; const a = pending; pending = null; go(a); }
  };
  return (arg) => { if (busy) { pending = arg; has = true; } else { go(arg); } };
}

function setStatus(text, error) {
  const s = $('status');
  s.textContent = text;
  s.classList.toggle('error', !!error);
}

// ------------------------------------------------------------ robots ----

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
  bindControls();
  resizeCanvases();
  new ResizeObserver(() => { resizeCanvases(); draw(); drawPlot(); }).observe($('view'));
  await loadRobot(def.name);
  document.body.dataset.ready = '1';
}

async function loadRobot(name) {
  stopPlayer();
  const res = await api(`/api/robots/${encodeURIComponent(name)}`);
  if (!res.ok) { setStatus(res.data.error, true); return; }
  const r = res.data;
  state.robot = r;
  state.q = r.home.slice();
  state.traj = null; state.manip = null; state.q3Anchor = null;
  const summary = state.robots.find((x) => x.name === name);
  $('robot-description').textContent = summary ? summary.description : '';
  buildSliders(r);
  buildPoses(r);
  $('q3-row').hidden = !r.ik.q3;
  if (r.ik.q3) {
    const j3 = r.joints[2];
    $('q3-slider').min = j3.min ?? -Math.PI; $('q3-slider').max = j3.max ?? Math.PI;
  }
  $('ik-solutions').tBodies[0].innerHTML = '';
  $('ik-message').textContent = '';
  $('program').value = defaultProgram(r);
  $('program-output').textContent = '';
  updatePlayerControls();
  drawPlot();
  // Frame the robot: its size from the home configuration.
  const fk = await api('/api/fk', { robot: r.name, q: state.q });
  if (fk.ok) {
    const pts = fk.data.frames.map((f) => f.position);
    let reach = 0;
    for (let i = 1; i < pts.length; i++) reach += dist3(pts[i], pts[i - 1]);
    state.reach = Math.max(reach, 0.2);
    resetView();
    applyFk(fk.data);
    fillIkFromTool();
  } else {
    setStatus(fk.data.error, true);
  }
  setStatus(`${r.name}: ${r.dof} joints`);
}

function jointRange(j) {
  const span = j.type === 'revolute' ? Math.PI : 1;
  return [j.min ?? -span, j.max ?? span];
}

function shownValue(j, v) {
  return j.type === 'revolute' ? `${(v * DEG).toFixed(1)}°` : `${(v * 1000).toFixed(1)} mm`;
}

function buildSliders(r) {
  const box = $('sliders');
  box.innerHTML = '';
  r.joints.forEach((j, i) => {
    const row = document.createElement('div');
    row.className = 'joint';
    const [lo, hi] = jointRange(j);
    row.innerHTML = `<span class="name" title="${j.name}">q${i + 1} ${j.name}</span>
      <input type="range" min="${lo}" max="${hi}" step="${j.type === 'revolute' ? 0.001 : 0.0005}" data-joint="${i + 1}">
      <span class="value"></span>`;
    const input = row.querySelector('input');
    input.value = state.q[i];
    input.addEventListener('input', () => {
      state.q[i] = parseFloat(input.value);
      state.q3Anchor = null;
      row.querySelector('.value').textContent = shownValue(j, state.q[i]);
      requestFk(state.q.slice());
    });
    row.querySelector('.value').textContent = shownValue(j, state.q[i]);
    box.appendChild(row);
  });
}

function buildPoses(r) {
  const box = $('poses');
  box.innerHTML = '';
  for (const name of Object.keys(r.poses)) {
    const b = document.createElement('button');
    b.type = 'button'; b.textContent = name;
    b.addEventListener('click', () => { stopPlayer(); setQ(r.poses[name]); });
    box.appendChild(b);
  }
}

// Moves the robot to `q`: sliders, q3 slider, FK.
function setQ(q, keepAnchor) {
  state.q = q.slice();
  if (!keepAnchor) state.q3Anchor = null;
  const rows = $('sliders').children;
  state.robot.joints.forEach((j, i) => {
    const row = rows[i];
    if (!row) return;
    row.querySelector('input').value = q[i];
    row.querySelector('.value').textContent = shownValue(j, q[i]);
  });
  requestFk(state.q.slice());
}

const requestFk = latestOnly(async (q) => {
  const res = await api('/api/fk', { robot: state.robot.name, q });
  if (!res.ok) { setStatus(res.data.error, true); return; }
  applyFk(res.data);
  if ($('show-ellipsoid').checked) await fetchManip(q);
});

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
  draw();
}

function applyFk(fk) {
  state.fk = fk;
  const rows = $('sliders').children;
  fk.joints.forEach((j, i) => rows[i] && rows[i].classList.toggle('out', !j.within_limits));
  const [x, y, z] = fk.position;
  const rpy = fk.rpy.map((a) => (a * DEG).toFixed(3));
  const T = fk.T.map((r) => r.map((v) => v.toFixed(4).padStart(8)).join(' ')).join('\n  ');
  const out = fk.out_of_limits.map((o) => `q${o.joint}`).join(', ');
  $('fk-readout').textContent =
    `x ${x.toFixed(4)}  y ${y.toFixed(4)}  z ${z.toFixed(4)} m\n` +
    `roll ${rpy[0]}°  pitch ${rpy[1]}°  yaw ${rpy[2]}° (zyx)\n` +
    `T =\n  ${T}\n` +
    (fk.within_limits ? 'all joints within limits' : `OUTSIDE limits: ${out}`);
  if (state.robot && state.robot.ik.q3 && state.fk.q.length > 2) {
    $('q3-slider').value = fk.q[2];
    $('q3-value').textContent = `${(fk.q[2] * DEG).toFixed(1)}°`;
  }
  draw();
}

// ---------------------------------------------------------------- IK ----

function fillIkFromTool() {
  if (!state.fk) return;
  const [x, y, z] = state.fk.position;
  const [r, p, w] = state.fk.rpy;
  $('ik-x').value = x.toFixed(4); $('ik-y').value = y.toFixed(4); $('ik-z').value = z.toFixed(4);
  $('ik-roll').value = (r * DEG).toFixed(2); $('ik-pitch').value = (p * DEG).toFixed(2); $('ik-yaw').value = (w * DEG).toFixed(2);
}

function ikTargetFromInputs() {
  const v = ['ik-x', 'ik-y', 'ik-z', 'ik-roll', 'ik-pitch', 'ik-yaw'].map((id) => parseFloat($(id).value));
  if (v.some((x) => !Number.isFinite(x))) return null;
  return { position: v.slice(0, 3), rpy: v.slice(3).map((a) => a / DEG) };
}

async function solveIk() {
  const target = ikTargetFromInputs();
  const msg = $('ik-message');
  if (!target) { msg.textContent = 'every target field must be a number'; msg.className = 'message'; return; }
  const body = { robot: state.robot.name, ...target, q0: state.q };
  if (state.robot.ik.q3) body.q3 = state.q[2];
  const res = await api('/api/ik', body);
  const tbody = $('ik-solutions').tBodies[0];
  tbody.innerHTML = '';
  if (!res.ok) { msg.textContent = res.data.error; msg.className = 'message'; return; }
  state.ikTarget = res.data.target.T;
  const sols = res.data.solutions;
  const within = sols.filter((s) => s.within_limits).length;
  msg.textContent = `${sols.length} solution(s) from the ${res.data.solver} solver` +
    (res.data.q3 !== null && res.data.q3 !== undefined ? ` at q3 = ${(res.data.q3 * DEG).toFixed(1)}°` : '') +
    `, ${within} within limits — click one to move there`;
  msg.className = 'message ok';
  sols.forEach((s, k) => {
    const tr = document.createElement('tr');
    const q = s.q.map((v, i) => state.robot.joints[i].type === 'revolute' ? (v * DEG).toFixed(1) : (v * 1000).toFixed(0) + 'mm');
    tr.innerHTML = `<td>${k + 1}</td><td>${s.branch}<div class="q">${q.join(' ')}</div></td>
      <td class="${s.within_limits ? '' : 'bad'}">${s.within_limits ? 'ok' : 'outside'}</td>
      <td>${(s.position_error * 1000).toExponential(1)} mm</td>
      <td><button type="button" class="ptp" title="animate a PTP motion to this solution">PTP</button></td>`;
    tr.addEventListener('click', (ev) => {
      if (ev.target.classList.contains('ptp')) return;
      stopPlayer();
      for (const other of tbody.children) other.classList.remove('picked');
      tr.classList.add('picked');
      setQ(s.q);
    });
    tr.querySelector('.ptp').addEventListener('click', () => planTraj({ kind: 'ptp', from: state.q, to: s.q, ...ptpLimits() }));
    tbody.appendChild(tr);
  });
}

// The iiwa's self-motion: IK at the anchored tool pose with the chosen q3,
// the solution nearest the current configuration.
const requestSelfMotion = latestOnly(async (q3) => {
  if (!state.q3Anchor) state.q3Anchor = state.fk.T;
  const res = await api('/api/ik', { robot: state.robot.name, T: state.q3Anchor, q3, q0: state.q });
  const msg = $('ik-message');
  if (!res.ok) {
    msg.textContent = `q3 = ${(q3 * DEG).toFixed(1)}°: ${res.data.error}`; msg.className = 'message';
    return;
  }
  const s = res.data.solutions[res.data.nearest ?? 0];
  msg.textContent = `self-motion: q3 = ${(q3 * DEG).toFixed(1)}°, branch ${s.branch}` +
    (s.within_limits ? '' : ' (outside joint limits)');
  msg.className = s.within_limits ? 'message ok' : 'message';
  setQ(s.q, true);
});

// ---------------------------------------------------------- player ----

function defaultProgram(r) {
  const names = Object.keys(r.poses);
  const lines = [`// ${r.name}: visit the named poses, 2.5 s per move.`];
  const num = (x, digits) => String(Number(x.toFixed(digits)));
  const literal = (q) => `JOINT(${q.map((v, i) => r.joints[i].type === 'revolute'
    ? `${num(v * DEG, 4)}deg` : `${num(v * 1000, 3)}mm`).join(', ')})`;
  const tag = (n) => 'p_' + n.replace(/[^A-Za-z0-9_]/g, '_');
  for (const n of names) lines.push(`POS ${tag(n)} = ${literal(r.poses[n])}`);
  for (const n of names) if (n !== 'home') lines.push(`PTP ${tag(n)} IN 2.5s`);
  lines.push('HOME 2.5s');
  return lines.join('\n') + '\n';
}

async function runProgram() {
  const out = $('program-output');
  out.textContent = 'running…'; out.className = 'message ok';
  const dt = parseFloat($('run-dt').value);
  const body = { robot: state.robot.name, program: $('program').value };
  if (Number.isFinite(dt)) body.dt = dt;
  const res = await api('/api/run', body);
  if (!res.ok) {
    out.textContent = res.data.diagnostics || res.data.error; out.className = 'message';
    return;
  }
  const d = res.data;
  out.textContent = `${d.motions.length} motion(s), ${d.duration.toFixed(3)} s, ${d.samples} samples` +
    (d.warnings.length ? '\n' + d.warnings_rendered : '');
  loadTraj({ t: d.t, q: d.q, source: 'program' });
}

// The robot's joint speed and acceleration limits; where the model has none,
// a moderate default (1 rad/s and 2 rad/s², 0.25 m/s and 0.5 m/s²).
function ptpLimits() {
  const js = state.robot.joints;
  return {
    jvel: js.map((j) => j.vel ?? (j.type === 'revolute' ? 1.0 : 0.25)),
    jacc: js.map((j) => j.acc ?? (j.type === 'revolute' ? 2.0 : 0.5)),
  };
}

async function planTraj(spec) {
  const res = await api('/api/traj', { robot: state.robot.name, dt: 0.01, ...spec });
  const msg = $('ik-message');
  if (!res.ok) { msg.textContent = res.data.error; msg.className = 'message'; return; }
  msg.textContent = `${spec.kind.toUpperCase()}: ${res.data.duration.toFixed(3)} s, ${res.data.samples} samples (player)`;
  msg.className = 'message ok';
  loadTraj({ t: res.data.t, q: res.data.q, source: spec.kind });
  play();
}

// Parses a trajectory CSV: a header naming t and q1..qn (other columns are
// ignored), or no header and the columns t, q1..qn first.
function parseCsv(text, dof) {
  const lines = text.split(/\r?\n/).map((l) => l.trim()).filter((l) => l && !l.startsWith('#'));
  if (!lines.length) throw new Error('the file is empty');
  const first = lines[0].split(',').map((c) => c.trim());
  let cols = [0, ...Array.from({ length: dof }, (_, i) => i + 1)];
  let start = 0;
  if (first.some((c) => c !== '' && !Number.isFinite(Number(c)))) {
    start = 1;
    const at = (name) => first.findIndex((c) => c.toLowerCase() === name);
    cols = [at('t'), ...Array.from({ length: dof }, (_, i) => at(`q${i + 1}`))];
    const missing = ['t', ...Array.from({ length: dof }, (_, i) => `q${i + 1}`)].filter((_, k) => cols[k] < 0);
    if (missing.length) throw new Error(`the header lacks the column(s) ${missing.join(', ')}; expected t,q1..q${dof}`);
  }
  const t = [], q = [];
  for (let k = start; k < lines.length; k++) {
    const f = lines[k].split(',');
    const vals = cols.map((c) => Number(f[c]));
    if (vals.some((v) => !Number.isFinite(v))) throw new Error(`line ${k + 1}: expected numbers in columns t,q1..q${dof}`);
    if (t.length && !(vals[0] > t[t.length - 1])) throw new Error(`line ${k + 1}: t must increase`);
    t.push(vals[0]); q.push(vals.slice(1));
  }
  if (t.length < 2) throw new Error('a trajectory needs at least two samples');
  return { t, q };
}

function loadTraj(traj) {
  stopPlayer();
  state.traj = traj;
  state.playTime = traj.t[0];
  updatePlayerControls();
  drawPlot();
  showTime(state.playTime);
}

function updatePlayerControls() {
  const tr = state.traj;
  $('play').disabled = !tr; $('time-slider').disabled = !tr;
  if (!tr) { $('time-label').textContent = 'no trajectory'; return; }
  $('time-slider').min = tr.t[0]; $('time-slider').max = tr.t[tr.t.length - 1];
  $('time-slider').step = Math.max((tr.t[tr.t.length - 1] - tr.t[0]) / 2000, 1e-4);
}

function qAt(tr, time) {
  const t = tr.t;
  if (time <= t[0]) return tr.q[0];
  if (time >= t[t.length - 1]) return tr.q[t.length - 1];
  let lo = 0, hi = t.length - 1;
  while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (t[mid] <= time) lo = mid; else hi = mid; }
  const s = (time - t[lo]) / (t[hi] - t[lo]);
  return tr.q[lo].map((v, i) => v + s * (tr.q[hi][i] - v));
}

function showTime(time) {
  const tr = state.traj;
  if (!tr) return;
  state.playTime = time;
  $('time-slider').value = time;
  $('time-label').textContent = `${time.toFixed(2)} / ${tr.t[tr.t.length - 1].toFixed(2)} s`;
  setQ(qAt(tr, time));
  drawPlot();
}

let lastFrame = null;
function tick(now) {
  if (!state.playing) return;
  const tr = state.traj;
  const speed = parseFloat($('play-speed').value) || 1;
  const dt = lastFrame === null ? 0 : (now - lastFrame) / 1000;
  lastFrame = now;
  let time = state.playTime + dt * speed;
  const end = tr.t[tr.t.length - 1];
  if (time >= end) { time = end; showTime(time); stopPlayer(); return; }
  showTime(time);
  requestAnimationFrame(tick);
}

function play() {
  const tr = state.traj;
  if (!tr) return;
  if (state.playTime >= tr.t[tr.t.length - 1]) state.playTime = tr.t[0];
  state.playing = true; lastFrame = null;
  $('play').textContent = 'pause';
  requestAnimationFrame(tick);
}

function stopPlayer() {
  state.playing = false;
  $('play').textContent = 'play';
}

// Joint values against time, one colour per joint, the cursor at playTime.
function drawPlot() {
  const c = $('plot'), g = c.getContext('2d');
  const w = c.width, h = c.height, dpr = window.devicePixelRatio || 1;
  g.setTransform(1, 0, 0, 1, 0, 0);
  g.clearRect(0, 0, w, h);
  g.scale(dpr, dpr);
  const W = w / dpr, H = h / dpr;
  const tr = state.traj;
  g.font = '11px system-ui, sans-serif';
  if (!tr || !state.robot) {
    g.fillStyle = '#8794a1';
    g.fillText('run a program, plan a PTP/LIN motion or load a CSV to see the joint curves', 12, H / 2);
    return;
  }
  const js = state.robot.joints;
  const conv = (v, i) => (js[i] && js[i].type === 'prismatic' ? v * 1000 : v * DEG);
  let lo = Infinity, hi = -Infinity;
  for (const q of tr.q) q.forEach((v, i) => { const y = conv(v, i); lo = Math.min(lo, y); hi = Math.max(hi, y); });
  if (hi - lo < 1e-9) { lo -= 1; hi += 1; }
  const pad = { l: 44, r: 90, t: 8, b: 20 };
  const t0 = tr.t[0], t1 = tr.t[tr.t.length - 1];
  const X = (t) => pad.l + (t - t0) / (t1 - t0 || 1) * (W - pad.l - pad.r);
  const Y = (v) => H - pad.b - (v - lo) / (hi - lo) * (H - pad.t - pad.b);
  g.strokeStyle = '#d9dee4'; g.fillStyle = '#5b6774'; g.lineWidth = 1;
  for (let k = 0; k <= 4; k++) {
    const v = lo + (hi - lo) * k / 4, y = Y(v);
    g.beginPath(); g.moveTo(pad.l, y); g.lineTo(W - pad.r, y); g.stroke();
    g.fillText(v.toFixed(0), 4, y + 4);
  }
  for (let k = 0; k <= 5; k++) {
    const t = t0 + (t1 - t0) * k / 5;
    g.fillText(`${t.toFixed(1)} s`, X(t) - 12, H - 5);
  }
  const step = Math.max(1, Math.floor(tr.t.length / 1500));
  js.forEach((j, i) => {
    g.strokeStyle = jointColour(i, js.length); g.lineWidth = 1.3;
    g.beginPath();
    for (let k = 0; k < tr.t.length; k += step) {
      const x = X(tr.t[k]), y = Y(conv(tr.q[k][i], i));
      if (k === 0) g.moveTo(x, y); else g.lineTo(x, y);
    }
    g.stroke();
    g.fillStyle = jointColour(i, js.length);
    g.fillText(`q${i + 1} [${j.type === 'prismatic' ? 'mm' : '°'}]`, W - pad.r + 8, pad.t + 12 + 13 * i);
  });
  g.strokeStyle = '#c62828'; g.lineWidth = 1.5;
  g.beginPath(); g.moveTo(X(state.playTime), pad.t); g.lineTo(X(state.playTime), H - pad.b); g.stroke();
}

function jointColour(i, n) {
  return `hsl(${Math.round(360 * i / Math.max(n, 1))}, 65%, 42%)`;
}

// --------------------------------------------------------- 3D view ----

function dist3(a, b) { return Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }
function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
function add(a, b) { return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]; }
function scale(a, s) { return [a[0] * s, a[1] * s, a[2] * s]; }
function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
function unit(a) { const n = Math.hypot(a[0], a[1], a[2]) || 1; return scale(a, 1 / n); }

function resetView() {
  const R = state.reach;
  state.camera = { yaw: -0.9, pitch: 0.38, dist: 1.9 * R, target: [0, 0, 0.38 * R] };
}

function camera() {
  const c = state.camera;
  const eye = add(c.target, [
    c.dist * Math.cos(c.pitch) * Math.cos(c.yaw),
    c.dist * Math.cos(c.pitch) * Math.sin(c.yaw),
    c.dist * Math.sin(c.pitch),
  ]);
  const f = unit(sub(c.target, eye));
  const r = unit(cross(f, [0, 0, 1]));
  const u = cross(r, f);
  return { eye, f, r, u };
}

function resizeCanvases() {
  const dpr = window.devicePixelRatio || 1;
  for (const c of [$('view'), $('plot')]) {
    const b = c.getBoundingClientRect();
    c.width = Math.max(1, Math.round(b.width * dpr));
    c.height = Math.max(1, Math.round(b.height * dpr));
  }
}

function draw() {
  const c = $('view'), g = c.getContext('2d');
  const dpr = window.devicePixelRatio || 1;
  const W = c.width / dpr, H = c.height / dpr;
  g.setTransform(dpr, 0, 0, dpr, 0, 0);
  const bg = g.createLinearGradient(0, 0, 0, H);
  bg.addColorStop(0, '#f7f9fc'); bg.addColorStop(1, '#dfe6ee');
  g.fillStyle = bg; g.fillRect(0, 0, W, H);
  if (!state.fk) return;
  const cam = camera();
  const focal = 1.1 * Math.min(W, H);
  const project = (p) => {
    const d = sub(p, cam.eye);
    const z = Math.max(dot(d, cam.f), 1e-3);
    return { x: W / 2 + focal * dot(d, cam.r) / z, y: H / 2 - focal * dot(d, cam.u) / z, z };
  };
  const R = state.reach;
  const prims = [];
  const line = (a, b, colour, width, cap) => {
    const pa = project(a), pb = project(b);
    prims.push({ z: (pa.z + pb.z) / 2, draw: () => {
      g.strokeStyle = colour; g.lineCap = cap || 'round';
      g.lineWidth = Math.max(1, width * focal / ((pa.z + pb.z) / 2));
      g.beginPath(); g.moveTo(pa.x, pa.y); g.lineTo(pb.x, pb.y); g.stroke();
    } });
  };
  const disc = (p, radius, fill, stroke) => {
    const pp = project(p);
    prims.push({ z: pp.z - 1e-4, draw: () => {
      const r = Math.max(2, radius * focal / pp.z);
      g.fillStyle = fill; g.beginPath(); g.arc(pp.x, pp.y, r, 0, 2 * Math.PI); g.fill();
      if (stroke) { g.strokeStyle = stroke; g.lineWidth = 1; g.stroke(); }
    } });
  };

  // Ground grid (z = 0), drawn first, below everything.
  const raw = R / 5, mag = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = mag * (raw / mag >= 5 ? 5 : raw / mag >= 2 ? 2 : 1);
  const n = Math.ceil(R / step);
  g.lineWidth = 1;
  for (let k = -n; k <= n; k++) {
    for (const [a, b] of [[[k * step, -n * step, 0], [k * step, n * step, 0]], [[-n * step, k * step, 0], [n * step, k * step, 0]]]) {
      const pa = project(a), pb = project(b);
      g.strokeStyle = k === 0 ? '#b7c2ce' : '#d3dae2';
      g.beginPath(); g.moveTo(pa.x, pa.y); g.lineTo(pb.x, pb.y); g.stroke();
    }
  }

  const frames = state.fk.frames;
  const showFrames = $('show-frames').checked;
  const axisLen = 0.07 * R;
  const triad = (f, len, width) => {
    const rot = f.rotation;
    ['#d62728', '#2ca02c', '#1f5fd6'].forEach((col, k) => {
      const axis = [rot[0][k], rot[1][k], rot[2][k]];
      line(f.position, add(f.position, scale(axis, len)), col, width);
    });
  };
  // Base plate.
  disc(frames[0].position, 0.06 * R, '#56616d', '#3b444d');
  // Links between consecutive frame origins.
  const linkWidth = 0.035 * R;
  for (let i = 1; i < frames.length; i++) {
    const a = frames[i - 1].position, b = frames[i].position;
    if (dist3(a, b) < 1e-9) continue;
    const light = 58 - 20 * i / frames.length;
    line(a, b, `hsl(212, 45%, ${light}%)`, linkWidth);
  }
  // Joints: a short cylinder along each axis.
  state.fk.joints.forEach((j, i) => {
    const half = scale(unit(j.axis), 0.045 * R);
    const colour = j.within_limits ? (j.type === 'prismatic' ? '#2e8b57' : '#e08a1e') : '#c62828';
    line(sub(j.origin, half), add(j.origin, half), colour, 0.05 * R, j.type === 'prismatic' ? 'butt' : 'round');
  });
  if (showFrames) {
    for (let i = 0; i < frames.length - 1; i++) triad(frames[i], axisLen, 0.006 * R);
  }
  // Tool frame and point, always shown.
  const tool = frames[frames.length - 1];
  triad(tool, 1.6 * axisLen, 0.009 * R);
  disc(tool.position, 0.014 * R, '#1d2733');
  // IK target, when one was asked for.
  if (state.ikTarget) {
    const T = state.ikTarget;
    const f = { position: [T[0][3], T[1][3], T[2][3]], rotation: T.slice(0, 3).map((r) => r.slice(0, 3)) };
    triad(f, axisLen, 0.004 * R);
    disc(f.position, 0.01 * R, 'rgba(140, 60, 200, 0.6)');
  }

  prims.sort((a, b) => b.z - a.z);
  for (const p of prims) p.draw();

  // Manipulability ellipsoid (translation), wireframe at the tool, on top.
  if ($('show-ellipsoid').checked && state.manip) {
    const e = state.manip.ellipsoid_translation;
    const k = parseFloat($('ellipsoid-scale').value) * R;
    const point = (u, v) => {
      let p = e.centre;
      const c = [Math.cos(u) * Math.cos(v), Math.sin(u) * Math.cos(v), Math.sin(v)];
      for (let a = 0; a < 3; a++) p = add(p, scale(e.axes[a], k * e.radii[a] * c[a]));
      return project(p);
    };
    g.strokeStyle = 'rgba(128, 40, 170, 0.55)'; g.lineWidth = 1;
    for (let m = 0; m < 12; m++) {
      const u = m * Math.PI / 6;
      g.beginPath();
      for (let s = 0; s <= 24; s++) { const p = point(u, -Math.PI / 2 + s * Math.PI / 24); if (s) g.lineTo(p.x, p.y); else g.moveTo(p.x, p.y); }
      g.stroke();
    }
    for (let l = 1; l < 8; l++) {
      const v = -Math.PI / 2 + l * Math.PI / 8;
      g.beginPath();
      for (let s = 0; s <= 36; s++) { const p = point(s * Math.PI / 18, v); if (s) g.lineTo(p.x, p.y); else g.moveTo(p.x, p.y); }
      g.stroke();
    }
    g.strokeStyle = 'rgba(128, 40, 170, 0.95)'; g.lineWidth = 2;
    for (let a = 0; a < 3; a++) {
      const p0 = project(add(e.centre, scale(e.axes[a], -k * e.radii[a])));
      const p1 = project(add(e.centre, scale(e.axes[a], k * e.radii[a])));
      g.beginPath(); g.moveTo(p0.x, p0.y); g.lineTo(p1.x, p1.y); g.stroke();
    }
  }
}

// ---------------------------------------------------------- controls ----

function bindControls() {
  const view = $('view');
  let drag = null;
  view.addEventListener('pointerdown', (e) => {
    drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button !== 0 };
    view.setPointerCapture(e.pointerId); view.classList.add('dragging');
  });
  view.addEventListener('pointermove', (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX; drag.y = e.clientY;
    const c = state.camera;
    if (drag.pan) {
      const cam = camera(), s = c.dist / (1.1 * Math.min(view.clientWidth, view.clientHeight));
      c.target = add(c.target, add(scale(cam.r, -dx * s), scale(cam.u, dy * s)));
    } else {
      c.yaw -= dx * 0.008;
      c.pitch = Math.min(1.5, Math.max(-1.5, c.pitch + dy * 0.008));
    }
    draw();
  });
  const end = () => { drag = null; view.classList.remove('dragging'); };
  view.addEventListener('pointerup', end);
  view.addEventListener('pointercancel', end);
  view.addEventListener('contextmenu', (e) => e.preventDefault());
  view.addEventListener('wheel', (e) => {
    e.preventDefault();
    state.camera.dist = Math.min(50 * state.reach, Math.max(0.2 * state.reach, state.camera.dist * Math.exp(e.deltaY * 0.0012)));
    draw();
  }, { passive: false });
  $('reset-view').addEventListener('click', () => { resetView(); draw(); });
  $('show-frames').addEventListener('change', draw);
  $('ellipsoid-scale').addEventListener('input', draw);
  $('show-ellipsoid').addEventListener('change', () => {
    $('manip-readout').hidden = !$('show-ellipsoid').checked;
    if ($('show-ellipsoid').checked) fetchManip(state.q.slice()); else draw();
  });
  $('ik-from-tool').addEventListener('click', fillIkFromTool);
  $('ik-solve').addEventListener('click', solveIk);
  $('ik-lin').addEventListener('click', () => {
    const target = ikTargetFromInputs();
    if (target) planTraj({ kind: 'lin', from: state.q, ...target });
  });
  $('q3-slider').addEventListener('pointerdown', () => { state.q3Anchor = state.fk ? state.fk.T : null; });
  $('q3-slider').addEventListener('input', () => {
    stopPlayer();
    const v = parseFloat($('q3-slider').value);
    $('q3-value').textContent = `${(v * DEG).toFixed(1)}°`;
    requestSelfMotion(v);
  });
  $('run-program').addEventListener('click', runProgram);
  $('csv-file').addEventListener('change', async () => {
    const file = $('csv-file').files[0];
    if (!file) return;
    const out = $('program-output');
    try {
      const tr = parseCsv(await file.text(), state.robot.dof);
      out.textContent = `${file.name}: ${tr.t.length} samples, ${(tr.t[tr.t.length - 1] - tr.t[0]).toFixed(3)} s`;
      out.className = 'message ok';
      loadTraj({ ...tr, source: file.name });
    } catch (e) {
      out.textContent = `${file.name}: ${e.message}`; out.className = 'message';
    }
  });
  $('play').addEventListener('click', () => (state.playing ? stopPlayer() : play()));
  $('time-slider').addEventListener('input', () => { stopPlayer(); showTime(parseFloat($('time-slider').value)); });
}

window.kinemaViewer = state;
init().catch((e) => setStatus(String(e), true));
