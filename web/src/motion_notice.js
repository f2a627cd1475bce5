// Tells the server when the camera starts and stops moving (POST /api/motion), while it has
// background work (the splat tree's fit, the scan's preparation): the work pauses meanwhile, so
// that the browser's drawing has the machine's cores (on the 2-core machine with SwiftShader
// the work took them while the page rotated: frame times of 60 to 160 ms instead of 35, issue
// 30). The server's pause lapses 3 s after the last word that the camera moves: renewed every
// RENEW_MS while it moves.
const RENEW_MS = 1000;

export class MotionNotice {
  constructor() {
    this.enabled = false;  // on while the server has background work
    this.moving = false;
    this.toldAt = 0;
  }

  /// Called when the camera starts or stops moving (after the page's settle time).
  setMoving(moving) {
    this.moving = moving;
    this.tell(moving);
  }

  /// Called on every change of the camera: renews the pause now and then while it moves.
  cameraChanged() {
    if (this.moving && performance.now() - this.toldAt > RENEW_MS) this.tell(true);
  }

  tell(moving) {
    if (!this.enabled) return;
    this.toldAt = performance.now();
    // Fire and forget: a lost word costs at most the pause's lapse (moving) or a pause (still).
    // An empty body, sent with Content-Length: 0 (cpp-httplib answers 400 to a POST without it).
    fetch(`/api/motion?moving=${moving ? 1 : 0}`, { method: 'POST', body: '', keepalive: true }).catch(() => {});
  }
}
