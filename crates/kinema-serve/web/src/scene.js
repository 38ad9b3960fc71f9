// The 3D view: a three.js renderer drawing on demand (when something moved),
// z up as in kinema, a floor grid, lights and orbit controls (drag: orbit,
// right-drag or shift-drag: pan, wheel: zoom).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

THREE.Object3D.DEFAULT_UP.set(0, 0, 1);

const BACKGROUND = 0xeef2f6;

export class View {
  constructor(canvas) {
    this.canvas = canvas;
    // Multisampling doubles a software renderer's frame time; a GPU does it for free.
    this.software = softwareRendering();
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: !this.software });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(BACKGROUND);
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 100);
    this.camera.up.set(0, 0, 1);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x8d99a6, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.8);
    sun.position.set(2, -3, 5);
    this.scene.add(sun);
    this.grid = null;
    this.framing = null;  // a THREE.Sphere the camera frames instead of the robot, or null
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.enableDamping = false;
    this.controls.addEventListener('change', () => this.requestRender());
    this.frames = 0;            // frames drawn
    this.frameTimes = [];       // the last drawing times [ms]
    this.pending = false;
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
  }

  // The WebGL version the browser gave: 'webgl2' or 'webgl'.
  get contextKind() {
    const gl = this.renderer.getContext();
    return typeof WebGL2RenderingContext !== 'undefined' && gl instanceof WebGL2RenderingContext ? 'webgl2' : 'webgl';
  }

  resize() {
    const w = Math.max(1, this.canvas.clientWidth), h = Math.max(1, this.canvas.clientHeight);
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.requestRender();
  }

  // A floor grid (z = 0) sized to the robot's reach, and the camera framing it.
  frame(reach) {
    this.framing = null;
    this.grid_(reach);
    this.camera.near = reach / 200;
    this.camera.far = reach * 60;
    this.resetCamera(reach);
  }

  // The camera and grid for everything in `box` (a THREE.Box3 [m]: a cell's
  // robots over their motion and the obstacles), kept for "reset view".
  frameBox(box, reach) {
    const sphere = box.getBoundingSphere(new THREE.Sphere());
    const size = Math.max(reach, 2 * sphere.radius);
    this.framing = sphere;
    this.grid_(size);
    this.camera.near = size / 200;
    this.camera.far = size * 60;
    this.resetCamera(reach);
  }

  grid_(reach) {
    if (this.grid) { this.scene.remove(this.grid); this.grid.geometry.dispose(); }
    const raw = reach / 5, mag = Math.pow(10, Math.floor(Math.log10(raw)));
    const step = mag * (raw / mag >= 5 ? 5 : raw / mag >= 2 ? 2 : 1);
    const cells = 2 * Math.ceil(1.5 * reach / step);
    this.grid = new THREE.GridHelper(cells * step, cells, 0xaab6c3, 0xcfd7df);
    this.grid.rotation.x = Math.PI / 2;
    this.scene.add(this.grid);
  }

  // The usual view of the robot (its reach [m]), or of the framed box: the
  // box's bounding sphere fits the narrower of the two fields of view.
  resetCamera(reach) {
    let target = new THREE.Vector3(0, 0, 0.38 * reach), dist = 2.4 * reach;
    if (this.framing) {
      const fov = THREE.MathUtils.degToRad(this.camera.fov);
      const narrow = Math.min(fov, 2 * Math.atan(Math.tan(fov / 2) * this.camera.aspect));
      target = this.framing.center.clone();
      dist = 1.1 * this.framing.radius / Math.sin(narrow / 2);
    }
    const yaw = -0.9, pitch = 0.38;
    this.camera.position.set(
      target.x + dist * Math.cos(pitch) * Math.cos(yaw),
      target.y + dist * Math.cos(pitch) * Math.sin(yaw),
      target.z + dist * Math.sin(pitch));
    this.controls.target.copy(target);
    this.controls.minDistance = 0.1 * reach;
    this.controls.maxDistance = 40 * Math.max(reach, dist);
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.requestRender();
  }

  requestRender() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => { this.pending = false; this.render(); });
  }

  render() {
    const start = performance.now();
    this.renderer.render(this.scene, this.camera);
    this.frames += 1;
    this.frameTimes.push(performance.now() - start);
    if (this.frameTimes.length > 120) this.frameTimes.shift();
  }

  // Where world point `p` ([x, y, z] m) is drawn: CSS pixels in the window.
  project(p) {
    const v = new THREE.Vector3(p[0], p[1], p[2]).project(this.camera);
    const r = this.canvas.getBoundingClientRect();
    return [r.left + (v.x + 1) / 2 * r.width, r.top + (1 - v.y) / 2 * r.height, v.z];
  }

  // The view as a PNG data URL (drawn again first: the drawing buffer is not kept).
  screenshot() {
    this.render();
    return this.canvas.toDataURL('image/png');
  }

  // Draws `count` frames, turning the camera a little each time, and
  // resolves with the median time per frame from one animation frame to the
  // next, and the median time to draw one completely [ms].
  measure(count) {
    const gl = this.renderer.getContext();
    const pixel = new Uint8Array(4);
    const intervals = [], draws = [];
    return new Promise((resolve) => {
      let last = null, k = 0;
      const step = (now) => {
        if (last !== null) intervals.push(now - last);
        last = now;
        this.controls.rotateLeft(0.01);
        this.controls.update();
        const start = performance.now();
        this.renderer.render(this.scene, this.camera);
        // Reading a pixel waits until the frame is really drawn (finish() may not).
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
        draws.push(performance.now() - start);
        this.frames += 1;
        if (++k < count) { requestAnimationFrame(step); return; }
        resolve({ frames: count, frame_ms: median(intervals), draw_ms: median(draws) });
      };
      requestAnimationFrame(step);
    });
  }
}

// Whether WebGL runs on the CPU (SwiftShader, llvmpipe: no GPU, as in
// headless browsers and virtual machines), from the renderer's name.
function softwareRendering() {
  const gl = document.createElement('canvas').getContext('webgl');
  if (!gl) return false;
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  const name = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
  const lose = gl.getExtension('WEBGL_lose_context');
  if (lose) lose.loseContext();
  return /swiftshader|llvmpipe|softpipe|software/i.test(name);
}

function median(xs) {
  const s = xs.slice().sort((a, b) => a - b);
  return s.length ? s[Math.floor(s.length / 2)] : null;
}
