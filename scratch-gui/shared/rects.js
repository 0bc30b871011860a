/*
 * Rectangles and points in page pixels, one shape for all: {x, y, width, height} (top-left
 * corner and size, CSS pixels of the 1280x720 viewport), as every bridge reply carries them.
 * Hit-testing lives here too: what a press at a point would reach is what the page says.
 */
scratchworldModule({name: 'rects', create() {
  'use strict';

  const right = (r) => r.x + r.width;
  const bottom = (r) => r.y + r.height;
  const centre = (r) => ({x: r.x + r.width / 2, y: r.y + r.height / 2});
  const inside = (r, x, y) => x >= r.x && x <= right(r) && y >= r.y && y <= bottom(r);
  const overlaps = (a, b) => a.x < right(b) && b.x < right(a) && a.y < bottom(b) && b.y < bottom(a);
  const grow = (r, by) => ({x: r.x - by, y: r.y - by, width: r.width + 2 * by, height: r.height + 2 * by});

  function rectOf(element) {
    const r = element.getBoundingClientRect();
    return {x: r.left, y: r.top, width: r.width, height: r.height};
  }

  function viewport() {
    return {x: 0, y: 0, width: window.innerWidth, height: window.innerHeight};
  }

  // The part of `r` inside `bounds` (zero-sized when they do not overlap).
  function clip(r, bounds) {
    const x = Math.max(r.x, bounds.x);
    const y = Math.max(r.y, bounds.y);
    return {x: x, y: y, width: Math.max(0, Math.min(right(r), right(bounds)) - x), height: Math.max(0, Math.min(bottom(r), bottom(bounds)) - y)};
  }

  // The part of `r` inside `bounds`, or null when they share no area.
  function intersection(r, bounds) {
    const part = clip(r, bounds);
    return part.width > 0 && part.height > 0 ? part : null;
  }

  // The smallest rect holding every non-empty rect of `rects`, or null when there is none.
  function union(rects) {
    const real = rects.filter((r) => r.width > 0 && r.height > 0);
    if (!real.length) return null;
    const x = Math.min(...real.map((r) => r.x));
    const y = Math.min(...real.map((r) => r.y));
    return {x: x, y: y, width: Math.max(...real.map(right)) - x, height: Math.max(...real.map(bottom)) - y};
  }

  // Whole pixels covering `r`, at least one each way (what element lists report).
  function rounded(r) {
    const x = Math.round(r.x);
    const y = Math.round(r.y);
    return {x: x, y: y, width: Math.max(1, Math.round(right(r)) - x), height: Math.max(1, Math.round(bottom(r)) - y)};
  }

  // Whether a press at (x, y) reaches `root` or something inside it.
  function hits(root, x, y) {
    const hit = document.elementFromPoint(x, y);
    return !!hit && (hit === root || root.contains(hit));
  }

  const centreHits = (root, r) => hits(root, r.x + r.width / 2, r.y + r.height / 2);

  return {
    right: right, bottom: bottom, centre: centre, inside: inside, overlaps: overlaps, grow: grow, rectOf: rectOf,
    viewport: viewport, clip: clip, intersection: intersection, union: union, rounded: rounded, hits: hits,
    centreHits: centreHits,
  };
}});
