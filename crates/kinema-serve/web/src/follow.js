// Follows what a program asks the page to show (Python's `robot.show` and
// `robot.animate` post it to /api/view): the page polls the server and
// applies each request once, in order of its version number.
import { api } from './api.js';

export class Follower {
  // `apply(shown)` shows one /api/view answer: {version, robot, q} or {version, robot, t, q}.
  constructor(apply, onError) {
    this.apply = apply;
    this.onError = onError;
    this.version = 0;
    this.busy = false;
  }

  start(periodMs) {
    setInterval(() => this.poll(), periodMs);
  }

  async poll() {
    if (this.busy) return;
    this.busy = true;
    try {
      const res = await api('/api/view');
      if (res.ok && res.data.version > this.version) {
        await this.apply(res.data);
        this.version = res.data.version;
      }
    } catch (e) {
      this.onError(e);
    } finally {
      this.busy = false;
    }
  }
}
