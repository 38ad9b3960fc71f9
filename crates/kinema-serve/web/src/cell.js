// A cell on a timeline (GET /api/cell, `kinema serve --cell`): every robot of
// the cell drawn at once, placed at each sample's link poses the server
// computed; play, pause, scrub and speed, ending on the last sample.
import { $ } from './state.js';
import * as THREE from 'three';
import { RobotModel } from './robot.js';

export class CellPlayer {
  constructor(view) {
    this.view = view;
    this.cell = null;
    this.models = [];
    this.k = 0;
    this.playing = false;
    this.time = 0;
  }

  get loaded() { return !!this.cell && this.cell.members.length > 0; }

  // Builds the members' shapes; `reach` [m] sizes their frame triads.
  load(cell, reach) {
    this.cell = cell;
    if (!this.loaded) return;
    this.models = cell.members.map((m) => {
      const model = new RobotModel(this.view);
      model.load(m.geometry, reach);
      model.showFrames(false);
      return model;
    });
    const slider = $('cell-time');
    slider.max = String(cell.times.length - 1);
    slider.addEventListener('input', () => { this.pause(); this.show(parseInt(slider.value, 10)); });
    $('cell-play').addEventListener('click', () => (this.playing ? this.pause() : this.play()));
    $('cell-row').hidden = false;
    this.show(0);
  }

  // Where the members go: every link frame origin at every sample, and their shapes at the sample shown.
  box() {
    const box = new THREE.Box3();
    for (const m of this.cell.members) {
      for (const sample of m.frames) for (const f of sample) box.expandByPoint(new THREE.Vector3(f[9], f[10], f[11]));
    }
    for (const model of this.models) box.expandByObject(model.root);
    return box;
  }

  setVisible(on) {
    for (const m of this.models) m.root.visible = on;
    this.view.requestRender();
  }

  // Places every member at sample k.
  show(k) {
    const c = this.cell;
    this.k = Math.max(0, Math.min(k, c.times.length - 1));
    this.time = c.times[this.k];
    c.members.forEach((m, i) => {
      const frames = m.frames[this.k].map((f) => ({
        rotation: [[f[0], f[1], f[2]], [f[3], f[4], f[5]], [f[6], f[7], f[8]]], position: [f[9], f[10], f[11]],
      }));
      this.models[i].setPose({ frames });
    });
    $('cell-time').value = String(this.k);
    const end = c.times[c.times.length - 1];
    $('cell-label').textContent = `${this.time.toFixed(2)} / ${end.toFixed(2)} s`;
    this.view.requestRender();
  }

  play() {
    const times = this.cell.times;
    if (this.k >= times.length - 1) this.show(0);
    this.playing = true;
    $('cell-play').textContent = 'pause';
    let last = performance.now();
    const step = (now) => {
      if (!this.playing) return;
      this.time += (now - last) / 1000 * parseFloat($('cell-speed').value);
      last = now;
      let k = this.k;
      while (k + 1 < times.length && times[k + 1] <= this.time) k++;
      const t = this.time;
      this.show(k);
      this.time = t;
      if (k >= times.length - 1) { this.pause(); return; }
      requestAnimationFrame(step);
    };
    requestAnimationFrame(step);
  }

  pause() {
    this.playing = false;
    $('cell-play').textContent = 'play';
  }

  // What the tests read: the sample shown and every member's joint values there.
  get status() {
    if (!this.loaded) return null;
    return {
      sample: this.k, samples: this.cell.times.length, time: this.time, playing: this.playing,
      members: this.cell.members.map((m) => ({ name: m.name, q: m.q[this.k] })),
    };
  }
}
