// The clip planes of the panel's settings: none, a half-space cut ("clip") or a slab of a
// given thickness, along one axis, placed as fractions of the model's bounds.
import * as THREE from 'three';

/// @param settings {mode: 'none'|'clip'|'slab', axis: 0|1|2, position: 0..1, thickness: 0..1, flip: bool}
/// @returns THREE.Plane[] keeping their positive side
export function clipPlanes(settings, bounds) {
  if (settings.mode === 'none') return [];
  const axis = new THREE.Vector3().setComponent(settings.axis, 1);
  const low = bounds.min.getComponent(settings.axis);
  const extent = bounds.max.getComponent(settings.axis) - low;
  const at = low + settings.position * extent;
  if (settings.mode === 'clip') {
    const keepAbove = settings.flip;
    return [new THREE.Plane(axis.clone().multiplyScalar(keepAbove ? 1 : -1), keepAbove ? -at : at)];
  }
  const half = (settings.thickness * extent) / 2;
  return [
    new THREE.Plane(axis.clone(), -(at - half)),
    new THREE.Plane(axis.clone().negate(), at + half),
  ];
}
