// The side panels: a slider per joint with the FK readout, and the IK panel
// (every solution listed, the iiwa's q3 self-motion slider).
import { $, DEG, state, setStatus } from './state.js';
import { api, latestOnly } from './api.js';
import { stopPlayer, planTraj, ptpLimits } from './player.js';

let viewer = null;  // { requestPose(q), redraw() } from main.js

export function bindPanels(v) {
  viewer = v;
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
}

function jointRange(j) {
  const span = j.type === 'revolute' ? Math.PI : 1;
  return [j.min ?? -span, j.max ?? span];
}

function shownValue(j, v) {
  return j.type === 'revolute' ? `${(v * DEG).toFixed(1)}°` : `${(v * 1000).toFixed(1)} mm`;
}

export function buildJointPanel(r) {
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
      viewer.requestPose(state.q.slice());
    });
    row.querySelector('.value').textContent = shownValue(j, state.q[i]);
    box.appendChild(row);
  });
  const poses = $('poses');
  poses.innerHTML = '';
  for (const name of Object.keys(r.poses)) {
    const b = document.createElement('button');
    b.type = 'button'; b.textContent = name;
    b.addEventListener('click', () => { stopPlayer(); setQ(r.poses[name]); });
    poses.appendChild(b);
  }
  $('q3-row').hidden = !r.ik.q3;
  if (r.ik.q3) {
    const j3 = r.joints[2];
    $('q3-slider').min = j3.min ?? -Math.PI; $('q3-slider').max = j3.max ?? Math.PI;
  }
  $('ik-solutions').tBodies[0].innerHTML = '';
  $('ik-message').textContent = '';
}

// Moves the robot to `q`: sliders, then the link poses from the server.
export function setQ(q, keepAnchor) {
  state.q = q.slice();
  if (!keepAnchor) state.q3Anchor = null;
  const rows = $('sliders').children;
  state.robot.joints.forEach((j, i) => {
    const row = rows[i];
    if (!row) return;
    row.querySelector('input').value = q[i];
    row.querySelector('.value').textContent = shownValue(j, q[i]);
  });
  viewer.requestPose(state.q.slice());
}

// The readout of an FK answer, and the sliders of joints outside their limits marked.
export function showFk(fk) {
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
  if (state.robot && state.robot.ik.q3 && fk.q.length > 2) {
    $('q3-slider').value = fk.q[2];
    $('q3-value').textContent = `${(fk.q[2] * DEG).toFixed(1)}°`;
  }
}

export function fillIkFromTool() {
  if (!state.fk) return;
  const [x, y, z] = state.fk.position;
  const [r, p, w] = state.fk.rpy;
  $('ik-x').value = x.toFixed(4); $('ik-y').value = y.toFixed(4); $('ik-z').value = z.toFixed(4);
  $('ik-roll').value = (r * DEG).toFixed(2); $('ik-pitch').value = (p * DEG).toFixed(2); $('ik-yaw').value = (w * DEG).toFixed(2);
}

export function ikTargetFromInputs() {
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
  viewer.redraw();
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
}, (e) => setStatus(String(e), true));
