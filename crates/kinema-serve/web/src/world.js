// What stands around the robot and how close it comes: the server's scene
// obstacles (GET /api/scene), the bodies in collision drawn red and the
// minimum-distance segment of the closest pair, from each /api/collide answer.
import * as THREE from 'three';
import { shapeObject, COLLIDING } from './robot.js';

const OBSTACLE = new THREE.MeshStandardMaterial({ color: 0x8a7f6e, metalness: 0.05, roughness: 0.8 });
const SEGMENT = new THREE.LineBasicMaterial({ color: 0x1a1aff, depthTest: false });
const WITNESS = new THREE.MeshBasicMaterial({ color: 0x1a1aff, depthTest: false });

export class World {
  constructor(view) {
    this.root = new THREE.Group();
    view.scene.add(this.root);
    this.obstacles = [];
    this.segment = new THREE.Line(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]), SEGMENT);
    this.segment.renderOrder = 3;
    this.segment.visible = false;
    this.ends = [0, 1].map(() => {
      const m = new THREE.Mesh(new THREE.SphereGeometry(1, 12, 8), WITNESS);
      m.renderOrder = 3;
      m.visible = false;
      return m;
    });
    view.scene.add(this.segment, ...this.ends);
  }

  // The obstacles of a scene answer ({obstacles: [shape]}, world frame).
  load(scene) {
    this.root.clear();
    this.obstacles = [];
    for (const s of scene.obstacles) {
      const object = shapeObject(s, OBSTACLE);
      if (object) { this.obstacles.push(object); this.root.add(object); }
    }
    this.root.updateMatrixWorld(true);
  }

  // Obstacles whose body is in `bodies` (a Set of names) in red.
  highlight(bodies) {
    for (const o of this.obstacles) o.material = bodies.has(o.userData.body) ? COLLIDING : o.userData.material;
  }

  // The segment between the closest pair's witness points (a /api/collide
  // `min_distance`), or none; `size` [m] is the radius of its end marks.
  setSegment(closest, size) {
    const on = !!closest;
    this.segment.visible = on;
    for (const e of this.ends) e.visible = on;
    if (!on) return;
    const [a, b] = [closest.point_a, closest.point_b].map((p) => new THREE.Vector3(...p));
    this.segment.geometry.setFromPoints([a, b]);
    this.ends[0].position.copy(a); this.ends[1].position.copy(b);
    for (const e of this.ends) { e.scale.setScalar(size); e.updateMatrixWorld(true); }
    this.segment.updateMatrixWorld(true);
  }
}
