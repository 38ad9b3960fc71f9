// A point cloud layer: positions, each with an optional value shown as a
// colour, read from a CSV such as `kinema reach --out` writes
// (x,y,z,reached,fraction). The value is the `fraction` column when there is
// one, else the fourth column; without one the points are grey.
import * as THREE from 'three';

export class PointCloud {
  constructor(view) {
    this.view = view;
    this.points = null;
    this.summary = null;
  }

  // Reads CSV text; throws an Error naming the first bad line.
  load(text, reach) {
    const lines = text.split(/\r?\n/).filter((l) => l.trim() && !l.trim().startsWith('#'));
    let column = 3;
    if (lines.length && /[a-z]/i.test(lines[0].split(',')[0])) {
      const names = lines.shift().split(',').map((n) => n.trim().toLowerCase());
      const fraction = names.indexOf('fraction');
      column = fraction >= 0 ? fraction : 3;
    }
    const xyz = new Float32Array(lines.length * 3), values = [];
    lines.forEach((line, i) => {
      const cells = line.split(',').map(Number);
      if (cells.length < 3 || cells.slice(0, 3).some((v) => !Number.isFinite(v))) {
        throw new Error(`point cloud: line ${i + 1} is not x,y,z[,value]: ${line}`);
      }
      xyz.set(cells.slice(0, 3), 3 * i);
      values.push(cells.length > column && Number.isFinite(cells[column]) ? cells[column] : null);
    });
    const known = values.filter((v) => v !== null);
    const lo = known.length ? Math.min(...known) : 0, hi = known.length ? Math.max(...known) : 0;
    const colours = new Float32Array(lines.length * 3);
    const c = new THREE.Color();
    values.forEach((v, i) => {
      if (v === null) c.setRGB(0.5, 0.5, 0.5);
      // Low values blue, high values red (hue 240° → 0°).
      else c.setHSL((1 - (hi > lo ? (v - lo) / (hi - lo) : 1)) * 2 / 3, 0.9, 0.5);
      colours.set([c.r, c.g, c.b], 3 * i);
    });
    this.clear();
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(xyz, 3));
    g.setAttribute('color', new THREE.BufferAttribute(colours, 3));
    this.points = new THREE.Points(g, new THREE.PointsMaterial({ size: 0.03 * reach, vertexColors: true }));
    this.view.scene.add(this.points);
    this.summary = { count: lines.length, valued: known.length, min: known.length ? lo : null, max: known.length ? hi : null };
    this.view.requestRender();
    return this.summary;
  }

  clear() {
    if (!this.points) return;
    this.view.scene.remove(this.points);
    this.points.geometry.dispose();
    this.points = null;
    this.summary = null;
    this.view.requestRender();
  }
}
