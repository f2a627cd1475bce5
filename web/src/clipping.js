// Caps on the cut faces, so a clipped closed mesh reads as a solid. For each plane, the
// model's back faces on the kept side add one to the stencil and its front faces subtract
// one: where the plane lies inside the solid the count is not zero, and the cap (a quad on
// the plane, cut by the other planes) is drawn there. The stencil is cleared after each cap.
import * as THREE from 'three';

const CAP_COLOUR = 0xc0603a;

function stencilMaterial(plane, side, operation) {
  return new THREE.MeshBasicMaterial({
    side, clippingPlanes: [plane], colorWrite: false, depthWrite: false, depthTest: false,
    stencilWrite: true, stencilFunc: THREE.AlwaysStencilFunc,
    stencilFail: operation, stencilZFail: operation, stencilZPass: operation,
  });
}

function capMaterial(otherPlanes) {
  return new THREE.MeshStandardMaterial({
    color: CAP_COLOUR, roughness: 0.8, side: THREE.DoubleSide, clippingPlanes: otherPlanes,
    stencilWrite: true, stencilRef: 0, stencilFunc: THREE.NotEqualStencilFunc,
    stencilFail: THREE.ReplaceStencilOp, stencilZFail: THREE.ReplaceStencilOp, stencilZPass: THREE.ReplaceStencilOp,
  });
}

export class ClipCaps {
  constructor(parent) {
    this.parent = parent;
    this.group = new THREE.Group();
    parent.add(this.group);
    this.planes = [];
    this.visible = true;
  }

  setGeometry(geometry) {
    this.geometry = geometry;
    this.rebuild();
  }

  setPlanes(planes, bounds, visible) {
    this.planes = planes;
    this.bounds = bounds;
    this.visible = visible;
    this.rebuild();
  }

  setVisible(visible) {
    this.visible = visible;
    this.group.visible = visible;
  }

  rebuild() {
    for (const child of [...this.group.children]) {
      child.material.dispose();
      if (child.isCap) child.geometry.dispose();
      this.group.remove(child);
    }
    this.group.visible = this.visible;
    if (!this.geometry) return;
    this.planes.forEach((plane, index) => this.addCap(plane, index));
  }

  /// The stencil passes and the cap of @a plane, drawn before the model (render order < 2).
  addCap(plane, index) {
    const order = index / this.planes.length;
    const back = new THREE.Mesh(this.geometry, stencilMaterial(plane, THREE.BackSide, THREE.IncrementWrapStencilOp));
    const front = new THREE.Mesh(this.geometry, stencilMaterial(plane, THREE.FrontSide, THREE.DecrementWrapStencilOp));
    back.renderOrder = front.renderOrder = order;
    const size = 2 * this.bounds.getSize(new THREE.Vector3()).length();
    const others = this.planes.filter((other) => other !== plane);
    const cap = new THREE.Mesh(new THREE.PlaneGeometry(size, size), capMaterial(others));
    cap.isCap = true;
    cap.renderOrder = order + 0.5 / this.planes.length;
    plane.projectPoint(this.bounds.getCenter(new THREE.Vector3()), cap.position);
    cap.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), plane.normal);
    cap.onAfterRender = (renderer) => renderer.clearStencil();
    this.group.add(back, front, cap);
  }
}
