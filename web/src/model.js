// The mesh on screen: solid, wireframe or both, flat or smooth shading, and cut by the clip
// planes with their caps (clipping.js); a label map's labels each in its colour, switchable.
// While the camera moves, a large mesh is drawn through its coarser proxy (motion_proxy.js).
import * as THREE from 'three';
import { ClipCaps } from './clipping.js';
import { motionGeometry } from './motion_proxy.js';

const SOLID_COLOUR = 0xd9cbb0;
const WIRE_ON_SOLID = 0x1c2230;
const WIRE_ALONE = 0x9fc4ff;

export class Model {
  /// @a caps false: no caps on the cut faces (for an open piece of a mesh, whose stencil count
  /// would not tell inside from outside).
  constructor(scene3d, { caps = true } = {}) {
    this.scene3d = scene3d;
    this.group = new THREE.Group();
    scene3d.scene.add(this.group);
    this.solidMaterial = new THREE.MeshStandardMaterial({
      color: SOLID_COLOUR, roughness: 0.6, metalness: 0.05, side: THREE.DoubleSide,
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    });
    this.wireMaterial = new THREE.MeshBasicMaterial({ color: WIRE_ALONE, wireframe: true });
    this.style = 'solid';
    this.caps = caps ? new ClipCaps(this.group) : null;
    this.planes = [];
    this.labelMaterials = [];
  }

  /// Shows @a geometry (a BufferGeometry with position, normal and index) instead of the last.
  /// @a labels (a label map's, from /api/info): each a run of the triangles, drawn in its
  /// colour and switchable (setLabelVisible).
  setGeometry(geometry, labels) {
    this.geometry?.dispose();
    this.geometry = geometry;
    this.group.remove(...this.group.children.filter((child) => child.isModelPart));
    let solid = this.solidMaterial;
    let wire = this.wireMaterial;
    this.labelMaterials = [];
    if (labels) {
      geometry.clearGroups();
      labels.forEach((label, i) => geometry.addGroup(3 * label.first_triangle, 3 * label.triangles, i));
      this.labelMaterials = labels.map((label) => {
        const material = { solid: this.solidMaterial.clone(), wire: this.wireMaterial.clone() };
        material.solid.color.setRGB(...label.colour, THREE.SRGBColorSpace);
        return material;
      });
      solid = this.labelMaterials.map((material) => material.solid);
      wire = this.labelMaterials.map((material) => material.wire);
    }
    this.solid = this.part(new THREE.Mesh(geometry, solid), 2);
    this.solid.castShadow = this.solid.receiveShadow = true;
    this.wire = this.part(new THREE.Mesh(geometry, wire), 3);
    this.caps?.setGeometry(geometry);
    this.proxy?.geometry.dispose();
    const proxy = labels ? null : motionGeometry(geometry);  // a label map's colours need its own triangles
    this.proxy = proxy && this.part(new THREE.Mesh(proxy, this.solidMaterial), 2);
    this.applyStyle();
  }

  /// Draws the coarser proxy (if the mesh has one) while @a moving.
  setMoving(moving) {
    this.moving = moving;
    this.applyStyle();
  }

  /// Draws label @a index (of those given to setGeometry) or not.
  setLabelVisible(index, visible) {
    this.labelMaterials[index].solid.visible = visible;
    this.labelMaterials[index].wire.visible = visible;
    this.scene3d.requestRender();
  }

  /// The materials in use: the shared ones, or each label's.
  solidMaterials() {
    return this.labelMaterials.length ? this.labelMaterials.map((material) => material.solid) : [this.solidMaterial];
  }

  wireMaterials() {
    return this.labelMaterials.length ? this.labelMaterials.map((material) => material.wire) : [this.wireMaterial];
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
    for (const material of [this.solidMaterial, ...this.solidMaterials()]) {
      material.flatShading = flat;
      material.needsUpdate = true;
    }
    this.scene3d.requestRender();
  }

  /// Cuts the model by @a planes (THREE.Plane, keeping their positive side), capped.
  setClipPlanes(planes, bounds) {
    this.planes = planes;
    for (const material of [this.solidMaterial, this.wireMaterial, ...this.solidMaterials(), ...this.wireMaterials()]) material.clippingPlanes = planes;
    this.caps?.setPlanes(planes, bounds, this.style !== 'wireframe');
    this.scene3d.requestRender();
  }

  applyStyle() {
    if (!this.solid) return;
    const proxied = Boolean(this.moving && this.proxy);
    this.solid.visible = !proxied && this.style !== 'wireframe';
    this.wire.visible = !proxied && this.style !== 'solid';
    if (this.proxy) {
      this.proxy.visible = proxied;
      this.proxy.material = this.style === 'wireframe' ? this.wireMaterial : this.solidMaterial;
    }
    for (const material of [this.wireMaterial, ...this.wireMaterials()]) material.color.set(this.style === 'both' ? WIRE_ON_SOLID : WIRE_ALONE);
    this.caps?.setVisible(!proxied && this.style !== 'wireframe');
    this.scene3d.requestRender();
  }
}
