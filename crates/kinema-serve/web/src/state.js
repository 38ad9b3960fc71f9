// What the page knows, shared by its modules; every number in it came from
// the server (the kinema library).

export const $ = (id) => document.getElementById(id);
export const DEG = 180 / Math.PI;

export const state = {
  robots: [],
  robot: null,        // GET /api/robots/{name}
  geometry: null,     // GET /api/robots/{name}/geometry
  q: [],
  fk: null,           // last FK answer (WebSocket or POST /api/fk)
  manip: null,        // last POST /api/manip answer
  collide: null,      // last POST /api/collide answer shown
  obstacles: 0,       // obstacles of the server's scene (GET /api/scene)
  reach: 1,
  ikTarget: null,     // pose of the last IK request (T rows)
  q3Anchor: null,     // tool pose kept while the q3 slider moves
  traj: null,         // { t: [], q: [[]], source }
  plan: null,         // { pending, ok, message, goal } of the last POST /api/plan
  playing: false,
  playTime: 0,
};

export function setStatus(text, error) {
  const s = $('status');
  s.textContent = text;
  s.classList.toggle('error', !!error);
}

export function dist3(a, b) { return Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }
