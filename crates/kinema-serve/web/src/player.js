// The player: a program run by the server, a planned PTP/LIN motion or a
// trajectory CSV, played on the 3D view with a time slider and joint plots.
import { $, DEG, state } from './state.js';
import { api } from './api.js';
import { setQ } from './panels.js';

export function bindPlayer() {
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
  new ResizeObserver(() => { resizePlot(); drawPlot(); }).observe($('plot'));
}

// A new robot: its default program, no trajectory.
export function resetPlayer(r) {
  stopPlayer();
  state.traj = null;
  $('program').value = defaultProgram(r);
  $('program-output').textContent = '';
  updatePlayerControls();
  drawPlot();
}

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
export function ptpLimits() {
  const js = state.robot.joints;
  return {
    jvel: js.map((j) => j.vel ?? (j.type === 'revolute' ? 1.0 : 0.25)),
    jacc: js.map((j) => j.acc ?? (j.type === 'revolute' ? 2.0 : 0.5)),
  };
}

export async function planTraj(spec) {
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

// Loads a trajectory {t, q, source} and plays it from its start.
export function playTrajectory(traj) {
  loadTraj(traj);
  play();
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

export function stopPlayer() {
  state.playing = false;
  $('play').textContent = 'play';
}

function resizePlot() {
  const c = $('plot'), dpr = window.devicePixelRatio || 1, b = c.getBoundingClientRect();
  c.width = Math.max(1, Math.round(b.width * dpr));
  c.height = Math.max(1, Math.round(b.height * dpr));
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
