// The mesh on screen: solid, wireframe or both, flat or smooth shading, and cut by the clip
// planes with their caps (clipping.js).
import * as THREE from 'three';
import { ClipCaps } from './clipping.js';

const SOLID_COLOUR = 0xd9cbb0;
const WIRE_ON_SOLID = 0x1c2230;
const WIRE_ALONE = 0x9fc4ff;

export class Model {
  constructor(scene3d) {
    this.scene3d = scene3d;
    this.group = new THREE.Group();
    scene3d.scene.add(this.group);
    this.solidMaterial = new THREE.MeshStandardMaterial({
      color: SOLID_COLOUR, roughness: 0.6, metalness: 0.05, side: THREE.DoubleSide,
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    });
    this.wireMaterial = new THREE.MeshBasicMaterial({ color: WIRE_ALONE, wireframe: true });
    this.style = 'solid';
    this.caps = new ClipCaps(this.group);
    this.planes = [];
  }

  /// Shows @a geometry (a BufferGeometry with position, normal and index) instead of the last.
  setGeometry(geometry) {
    this.geometry?.dispose();
    this.geometry = geometry;
    this.group.remove(...this.group.children.filter((child) => child.isModelPart));
    this.solid = this.part(new THREE.Mesh(geometry, this.solidMaterial), 2);
    this.solid.castShadow = this.solid.receiveShadow = true;
    this.wire = this.part(new THREE.Mesh(geometry, this.wireMaterial), 3);
    this.caps.setGeometry(geometry);
    this.applyStyle();
  }

  part(mesh, renderOrder) {
    mesh.isModelPart = true;
    mesh.renderOrder = renderOrder;
    this.group.add(mesh);
    return mesh;
  }

  /// 'solid', 'wireframe' or 'both'.
  setStyle(style) {
    this.style = style;
    this.applyStyle();
  }

  setFlatShading(flat) {
    this.solidMaterial.flatShading = flat;
    this.solidMaterial.needsUpdate = true;
    this.scene3d.requestRender();
  }

  /// Cuts the model by @a planes (THREE.Plane, keeping their positive side), capped.
  setClipPlanes(planes, bounds) {
    this.planes = planes;
    this.solidMaterial.clippingPlanes = planes;
    this.wireMaterial.clippingPlanes = planes;
    this.caps.setPlanes(planes, bounds, this.style !== 'wireframe');
    this.scene3d.requestRender();
  }

  applyStyle() {
    if (!this.solid) return;
    this.solid.visible = this.style !== 'wireframe';
    this.wire.visible = this.style !== 'solid';
    this.wireMaterial.color.set(this.style === 'both' ? WIRE_ON_SOLID : WIRE_ALONE);
    this.caps.setVisible(this.style !== 'wireframe');
    this.scene3d.requestRender();
  }
}
