// Pixel measures of screenshots (PNG buffers): what the browser test checks the page by.
import { createRequire } from 'node:module';

/// Decodes PNGs with pngjs from @a webDir's node_modules.
export function pngDecoder(webDir) {
  const { PNG } = createRequire(`${webDir}/package.json`)('pngjs');
  return (buffer) => PNG.sync.read(buffer);
}

const differs = (data, i, colour, tolerance) =>
  Math.abs(data[i] - colour[0]) + Math.abs(data[i + 1] - colour[1]) + Math.abs(data[i + 2] - colour[2]) > tolerance;

/// The pixels that differ from @a background: their count, share, bounding box and the
/// counts left and right of the image's middle.
export function foreground(image, background, tolerance = 24) {
  let count = 0, left = 0, right = 0;
  const box = { minX: image.width, minY: image.height, maxX: -1, maxY: -1 };
  for (let y = 0; y < image.height; ++y) {
    for (let x = 0; x < image.width; ++x) {
      if (!differs(image.data, 4 * (y * image.width + x), background, tolerance)) continue;
      ++count;
      if (x < image.width / 2) ++left; else ++right;
      box.minX = Math.min(box.minX, x); box.maxX = Math.max(box.maxX, x);
      box.minY = Math.min(box.minY, y); box.maxY = Math.max(box.maxY, y);
    }
  }
  return { count, share: count / (image.width * image.height), left, right, box };
}

/// The share of pixels that differ between two images of the same size.
export function changedShare(a, b, tolerance = 24) {
  let changed = 0;
  for (let i = 0; i < a.data.length; i += 4) {
    if (differs(a.data, i, [b.data[i], b.data[i + 1], b.data[i + 2]], tolerance)) ++changed;
  }
  return changed / (a.width * a.height);
}

/// The share of pixels for which @a predicate(r, g, b) holds.
export function shareWhere(image, predicate) {
  let matching = 0;
  for (let i = 0; i < image.data.length; i += 4) if (predicate(image.data[i], image.data[i + 1], image.data[i + 2])) ++matching;
  return matching / (image.width * image.height);
}
