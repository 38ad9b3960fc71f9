// Planning: a collision-free motion from the current configuration to a
// typed configuration or a tool pose (the gizmo's while it is on, else the
// IK fields'), found by the server (POST /api/plan, around the robot itself
// and the server's scene) and played on the player.
import { $, DEG, state } from './state.js';
import { api } from './api.js';
import { playTrajectory, stopPlayer } from './player.js';

let goalPose = null;  // () => {pose} | null, from main.js

export function bindPlan(pose) {
  goalPose = pose;
  $('plan').addEventListener('click', planMotion);
}

// A typed configuration: degrees for revolute joints, millimetres for
// prismatic ones, separated by commas or spaces.
function typedQ(text) {
  const js = state.robot.joints;
  const v = text.split(/[\s,]+/).filter((s) => s !== '').map(Number);
  if (v.some((x) => !Number.isFinite(x))) throw new Error(`goal q: \`${text}\` is not a list of numbers`);
  return v.map((x, i) => (js[i] && js[i].type === 'prismatic' ? x / 1000 : x / DEG));
}

async function planMotion() {
  const msg = $('plan-message');
  const say = (text, ok) => { msg.textContent = text; msg.className = ok ? 'message ok' : 'message'; };
  let goal;
  try {
    const text = $('plan-q').value.trim();
    goal = text ? { to: typedQ(text) } : goalPose();
  } catch (e) { say(e.message, false); return; }
  if (!goal) { say('give a goal: type joint values, turn the gizmo on, or fill the IK fields', false); return; }
  stopPlayer();
  state.plan = { pending: true, ok: null, message: '' };
  say('planning…', true);
  const body = { robot: state.robot.name, from: state.q.slice(), ...goal, time_limit: 5 };
  const dt = parseFloat($('run-dt').value);
  if (Number.isFinite(dt)) body.dt = dt;
  const res = await api('/api/plan', body);
  if (!res.ok) {
    state.plan = { pending: false, ok: false, message: res.data.error };
    say(res.data.error, false);
    return;
  }
  const d = res.data, p = d.plan;
  const text = `planned in ${(p.planning_time * 1000).toFixed(0)} ms: ${p.via_points.length} via points, ` +
    `${d.duration.toFixed(3)} s, ${d.samples} samples`;
  state.plan = { pending: false, ok: true, message: text, goal: d.q[d.q.length - 1] };
  say(text, true);
  playTrajectory({ t: d.t, q: d.q, source: 'plan' });
}
