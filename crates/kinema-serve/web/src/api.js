// The server's JSON API over HTTP, and the WebSocket that answers joint
// values with link poses (FK) as the sliders move.

export async function api(path, body) {
  const init = body === undefined ? {} : {
    method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body),
  };
  const res = await fetch(path, init);
  let data = null;
  try { data = await res.json(); } catch (e) { data = { error: `${path}: the answer is not JSON (${res.status})` }; }
  return { ok: res.ok, status: res.status, data };
}

// Runs `fn(arg)` with at most one call in flight; while one runs, only the
// latest argument is kept and sent next (sliders stay smooth, nothing queues up).
export function latestOnly(fn, onError) {
  let busy = false, pending = null, has = false;
  const go = async (arg) => {
    busy = true;
    try { await fn(arg); } catch (e) { onError(e); }
    busy = false;
    if (has) { has = false; const a = pending; pending = null; go(a); }
  };
  return (arg) => { if (busy) { pending = arg; has = true; } else { go(arg); } };
}

// Link poses for joint values: one request in flight on the WebSocket
// `/api/ws` (the latest values wait for its answer), or POST /api/fk while
// the socket is not open.
export class PoseLink {
  constructor(onPose, onError) {
    this.onPose = onPose;
    this.onError = onError;
    this.inFlight = false;
    this.pending = null;
    this.socket = null;
    this.post = latestOnly(async (req) => this.answer(await api('/api/fk', req)), onError);
    this.connect();
  }

  connect() {
    const url = `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/api/ws`;
    const socket = new WebSocket(url);
    socket.addEventListener('message', (ev) => {
      this.inFlight = false;
      let data;
      try { data = JSON.parse(ev.data); } catch (e) { data = { error: '/api/ws: the answer is not JSON' }; }
      this.answer({ ok: !data.error, data });
      this.flush();
    });
    socket.addEventListener('close', () => {
      this.socket = null;
      this.inFlight = false;
      this.flush();
    });
    socket.addEventListener('open', () => { this.socket = socket; this.flush(); });
  }

  answer(res) {
    if (res.ok) this.onPose(res.data); else this.onError(res.data.error);
  }

  // Asks for the poses of `robot` at `q`; answers come in order, stale ones skipped.
  request(robot, q) {
    this.pending = { robot, q };
    this.flush();
  }

  flush() {
    if (!this.pending || this.inFlight) return;
    const req = this.pending;
    this.pending = null;
    if (this.socket && this.socket.readyState === WebSocket.OPEN) {
      this.inFlight = true;
      this.socket.send(JSON.stringify(req));
    } else {
      this.post(req);
    }
  }

  // Whether answers come over the WebSocket.
  get live() { return !!this.socket && this.socket.readyState === WebSocket.OPEN; }
}
