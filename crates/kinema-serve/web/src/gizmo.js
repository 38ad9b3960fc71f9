// Dragging the tool: three's TransformControls on a handle at the tool pose.
// While the handle moves, the server solves IK toward its pose from the
// current configuration (the solution nearest it; a redundant arm keeps its
// q3). An unreachable pose is said so, and the robot shows the closest
// configuration the server found — the handle stays where it was dropped.
import * as THREE from 'three';
import { TransformControls } from 'three/addons/controls/TransformControls.js';
import { $, DEG, state, setStatus } from './state.js';
import { api, latestOnly } from './api.js';
import { setQ } from './panels.js';
import { rowsMatrix } from './robot.js';

export class Gizmo {
  constructor(view) {
    this.view = view;
    this.handle = new THREE.Object3D();
    view.scene.add(this.handle);
    this.controls = new TransformControls(view.camera, view.canvas);
    this.controls.setSize(0.8);
    this.controls.enabled = false;
    this.helper = this.controls.getHelper();
    this.helper.visible = false;
    view.scene.add(this.helper);
    // What the page last asked and heard, for the panel and the tests.
    this.status = { target: null, pending: false, reached: null, closest: null, message: '' };
    this.held = false;   // the handle stays at an unreachable target
    this.controls.addEventListener('change', () => view.requestRender());
    this.controls.addEventListener('dragging-changed', (e) => {
      view.controls.enabled = !e.value;
      if (e.value) this.held = false;
    });
    this.controls.addEventListener('objectChange', () => this.follow(this.target()));
    this.follow = latestOnly((target) => this.solve(target), (e) => setStatus(String(e), true));
  }

  // Shows or hides the handle (at the tool).
  enable(on) {
    this.controls.enabled = on;
    this.helper.visible = on;
    this.held = false;
    if (on) this.controls.attach(this.handle); else this.controls.detach();
    if (on && state.fk) this.place(state.fk.T);
    this.view.requestRender();
  }

  setMode(mode) { this.controls.setMode(mode); }

  // The handle's size as drawn [m per gizmo unit]: its arrows reach out 0.6,
  // its rings have radius 0.5 (three.js scales them with the camera distance
  // at each frame). Tests aim the mouse at the arrows and rings with it.
  get drawnScale() {
    const picker = this.controls._gizmo.picker[this.controls.mode];
    return picker.children.length ? picker.children[0].scale.x : null;
  }

  // The handle's centre [m], world frame.
  get centre() { return this.handle.position.toArray(); }

  // The handle goes back to the tool at the next pose.
  release() { this.held = false; }

  // Puts the handle at the tool pose T (4 rows), unless it is being dragged
  // or holds an unreachable target.
  place(T) {
    if (!this.controls.enabled || this.controls.dragging || this.held) return;
    rowsMatrix(T).decompose(this.handle.position, this.handle.quaternion, this.handle.scale);
    this.handle.updateMatrixWorld(true);
  }

  // The handle's pose as 4 rows.
  target() {
    this.handle.updateMatrixWorld(true);
    const e = this.handle.matrixWorld.elements;
    return [0, 1, 2, 3].map((r) => [e[r], e[r + 4], e[r + 8], e[r + 12]]);
  }

  async solve(T) {
    const r = state.robot;
    this.status = { ...this.status, target: T, pending: true };
    const body = { robot: r.name, T, q0: state.q };
    if (r.ik.q3) body.q3 = state.q[2];
    let res = await api('/api/ik', body);
    if (res.ok) {
      const s = res.data.solutions[res.data.nearest ?? res.data.picked ?? 0];
      this.show(T, s.q, null, `gizmo: tool at the target, branch ${s.branch}` +
        (s.within_limits ? '' : ' (outside joint limits)'));
      return;
    }
    const reason = res.data.error;
    let closest = res.data.closest;
    // A closed-form solver says why a pose is out of reach but gives no
    // nearest configuration: the numeric solver searches from q (and may
    // reach the pose with another q3).
    if (!closest && res.status === 422 && /unreachable/.test(reason)) {
      res = await api('/api/ik', { robot: r.name, T, q0: state.q, solver: 'numeric' });
      if (res.ok) {
        const q = res.data.solutions[res.data.nearest ?? 0].q;
        this.show(T, q, null, `gizmo: tool at the target by the numeric solver` +
          (r.ik.q3 ? ` with q3 = ${(q[2] * DEG).toFixed(1)}° (none at q3 = ${(state.q[2] * DEG).toFixed(1)}°)` : ''));
        return;
      }
      closest = res.data.closest;
    }
    if (!closest) { this.show(T, null, null, `gizmo: ${reason}`); return; }
    this.show(T, closest.q, closest, `UNREACHABLE — the robot shows the closest configuration the server found ` +
      `(misses by ${(closest.position_error * 1000).toFixed(1)} mm, ${(closest.orientation_error * DEG).toFixed(2)}°): ${reason}`);
  }

  // The outcome of one IK request: the robot moved to q (a solution, or the
  // closest configuration when `closest` is given; none when q is null).
  show(T, q, closest, message) {
    const reached = !!q && !closest;
    this.status = { target: T, pending: false, reached, closest, message };
    if (!reached) this.held = true;
    const msg = $('ik-message');
    msg.textContent = message;
    msg.className = reached ? 'message ok' : 'message';
    if (q) setQ(q, true);
  }
}
