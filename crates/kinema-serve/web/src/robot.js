// The robot in the 3D view: its link shapes built once from the geometry
// answer (in link frames), then moved by the link poses of each FK answer.
// A robot without shapes is drawn as rods between its frame origins.
import * as THREE from 'three';

const VISUAL = new THREE.MeshStandardMaterial({ color: 0xb8c2cc, metalness: 0.15, roughness: 0.55 });
const LINK_COLOURS = [0x5b6673, 0xe0812a, 0xc9d1d9];
const COLLISION = new THREE.MeshBasicMaterial({ color: 0xd0452f, transparent: true, opacity: 0.3, depthWrite: false });
const ROD = new THREE.MeshStandardMaterial({ color: 0x4f7cad, metalness: 0.1, roughness: 0.6 });
// A body in collision (a link or an obstacle), whatever its own colour.
export const COLLIDING = new THREE.MeshStandardMaterial({ color: 0xff1a1a, metalness: 0.05, roughness: 0.7 });

export class RobotModel {
  constructor(view) {
    this.view = view;
    this.root = new THREE.Group();
    view.scene.add(this.root);
    this.links = [];      // one group per link, placed at its frame
    this.axes = [];       // one triad per frame (base, links, tool)
    this.collision = [];  // the collision shapes' objects
    this.drawn = [];      // the shapes drawn solid, each with its body's name
    this.rods = null;     // the stand-in for a robot without shapes
    this.tool = null;
    this.target = null;
    this.ellipsoid = null;
  }

  // Builds the links from GET /api/robots/{name}/geometry; `reach` [m] sizes the frame triads.
  load(geometry, reach) {
    this.root.clear();
    this.links = []; this.axes = []; this.collision = []; this.drawn = []; this.rods = null;
    for (let i = 0; i < geometry.links; i++) {
      const g = new THREE.Group();
      g.matrixAutoUpdate = false;
      this.links.push(g);
      this.root.add(g);
    }
    const drawn = geometry.visual.length ? geometry.visual : geometry.collision;
    for (const s of drawn) {
      const material = geometry.visual.length ? VISUAL : linkMaterial(s.link, geometry.links);
      const object = this.addShape(s, material);
      if (object) this.drawn.push(object);
    }
    if (geometry.visual.length) {
      for (const s of geometry.collision) this.collision.push(this.addShape(s, COLLISION));
    }
    if (!drawn.length) this.rods = new Rods(this.root, geometry.links + 1, reach);
    for (let i = 0; i <= geometry.links; i++) {
      const a = new THREE.AxesHelper((i === geometry.links ? 0.11 : 0.07) * reach);
      a.matrixAutoUpdate = false;
      a.material.depthTest = false;
      a.renderOrder = 2;
      this.axes.push(a);
      this.root.add(a);
    }
    this.target = new THREE.AxesHelper(0.08 * reach);
    this.target.matrixAutoUpdate = false;
    this.target.visible = false;
    this.root.add(this.target);
    this.ellipsoid = new THREE.Mesh(new THREE.SphereGeometry(1, 24, 12),
      new THREE.MeshBasicMaterial({ color: 0x8028aa, wireframe: true, transparent: true, opacity: 0.5 }));
    this.ellipsoid.matrixAutoUpdate = false;
    this.ellipsoid.visible = false;
    this.root.add(this.ellipsoid);
  }

  addShape(s, material) {
    const object = shapeObject(s, material);
    if (!object) return null;
    this.links[s.link].add(object);
    return object;
  }

  // Places every link at its frame of an FK answer (`frames`: base, links 1..n, tool).
  setPose(fk) {
    const frames = fk.frames;
    this.links.forEach((g, i) => frames[i] && g.matrix.copy(frameMatrix(frames[i])));
    this.axes.forEach((a, i) => frames[i] && a.matrix.copy(frameMatrix(frames[i])));
    if (this.rods) this.rods.set(frames.map((f) => f.position));
    this.root.updateMatrixWorld(true);
  }

  // Draws the links named in `bodies` (a Set of link names, as /api/collide
  // names pairs) in red, the others in their own colours.
  highlight(bodies) {
    for (const m of this.drawn) m.material = bodies.has(m.userData.body) ? COLLIDING : m.userData.material;
  }

  showFrames(on) {
    // The tool's triad stays: it is what IK targets.
    this.axes.forEach((a, i) => { a.visible = on || i === this.axes.length - 1; });
  }

  showCollision(on) {
    for (const c of this.collision) if (c) c.visible = on;
  }

  // The IK target's triad (T: 4 rows), or none.
  setTarget(T) {
    this.target.visible = !!T;
    if (T) this.target.matrix.copy(rowsMatrix(T));
    this.target.updateMatrixWorld(true);
  }

  // The translational manipulability ellipsoid of a POST /api/manip answer, radii × `scale`, or none.
  setEllipsoid(manip, scale) {
    this.ellipsoid.visible = !!manip;
    if (!manip) return;
    const e = manip.ellipsoid_translation;
    const [a, b, c] = e.axes.map((v, k) => new THREE.Vector3(...v).multiplyScalar(Math.max(e.radii[k] * scale, 1e-6)));
    this.ellipsoid.matrix.makeBasis(a, b, c).setPosition(...e.centre);
    this.ellipsoid.updateMatrixWorld(true);
  }
}

// Shape objects in their link frame (an obstacle's: the world frame); for a
// shape kind the page does not know, none.
export function shapeObject(s, material) {
  let geometry;
  switch (s.kind) {
    case 'sphere': geometry = new THREE.SphereGeometry(s.radius, 32, 16); break;
    case 'box': geometry = new THREE.BoxGeometry(...s.size); break;
    // three's round shapes stand along y, kinema's along z.
    case 'cylinder': geometry = new THREE.CylinderGeometry(s.radius, s.radius, s.length, 32).rotateX(Math.PI / 2); break;
    case 'capsule': geometry = new THREE.CapsuleGeometry(s.radius, s.length, 8, 24).rotateX(Math.PI / 2); break;
    case 'mesh': geometry = meshGeometry(s.mesh); break;
    default: return null;
  }
  const mesh = new THREE.Mesh(geometry, material);
  mesh.matrixAutoUpdate = false;
  mesh.matrix.copy(rowsMatrix(s.pose));
  mesh.name = s.name;
  mesh.userData = { body: s.body, material };
  return mesh;
}

function meshGeometry(m) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(bytes(m.vertices).buffer), 3));
  g.setIndex(new THREE.BufferAttribute(new Uint32Array(bytes(m.triangles).buffer), 1));
  g.computeVertexNormals();
  return g;
}

// base64 → bytes (little-endian arrays: the byte order of every WebGL platform).
function bytes(text) {
  const raw = atob(text);
  const out = new Uint8Array(raw.length);
  for (let i = 0; i < raw.length; i++) out[i] = raw.charCodeAt(i);
  return out;
}

function linkMaterial(link, links) {
  const colour = link === 0 ? LINK_COLOURS[0] : LINK_COLOURS[1 + (link % 2)];
  return new THREE.MeshStandardMaterial({ color: colour, metalness: 0.1, roughness: 0.6 });
}

// A 4×4 matrix from 4 rows of 4 numbers.
export function rowsMatrix(T) {
  const m = new THREE.Matrix4();
  m.set(...T[0], ...T[1], ...T[2], 0, 0, 0, 1);
  return m;
}

// A frame answer ({position, rotation rows}) as a 4×4 matrix.
function frameMatrix(f) {
  const r = f.rotation, p = f.position;
  return new THREE.Matrix4().set(r[0][0], r[0][1], r[0][2], p[0], r[1][0], r[1][1], r[1][2], p[1],
    r[2][0], r[2][1], r[2][2], p[2], 0, 0, 0, 1);
}

// Rods from each frame origin to the next, for a robot without shapes.
class Rods {
  constructor(parent, count, reach) {
    this.rods = [];
    const radius = 0.02 * reach;
    for (let i = 0; i + 1 < count; i++) {
      const rod = new THREE.Mesh(new THREE.CylinderGeometry(radius, radius, 1, 16).translate(0, 0.5, 0), ROD);
      rod.matrixAutoUpdate = false;
      this.rods.push(rod);
      parent.add(rod);
    }
  }

  set(points) {
    const up = new THREE.Vector3(0, 1, 0);
    this.rods.forEach((rod, i) => {
      const a = new THREE.Vector3(...points[i]), b = new THREE.Vector3(...(points[i + 1] || points[i]));
      const d = b.clone().sub(a), len = d.length();
      rod.visible = len > 1e-9;
      if (!rod.visible) return;
      const q = new THREE.Quaternion().setFromUnitVectors(up, d.divideScalar(len));
      rod.matrix.compose(a, q, new THREE.Vector3(1, len, 1));
    });
  }
}
