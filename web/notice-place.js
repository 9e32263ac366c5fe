// Where the notices go over the view: in the corner that hides the least
// of the arm. A stop is shown with the arm at rest, and the person looks
// at the arm to see why it stopped: a fixed corner covered the base of a
// planar arm (chattering) or the links of one reached by a person at
// 800×600. The notices stay where they are while they hide nothing; they
// move only when notices come or go. On a phone (a narrow widget) they run
// across the bottom of the view, whatever the corner (style.js).

/** The corners tried, in the order preferred when several hide nothing. */
const CORNERS = ['bottom-left', 'top-left', 'bottom-right'];
/** Points sampled along each link between two nodes. */
const PER_LINK = 10;

/**
 * The arm on screen in CSS pixels from the view's top-left corner: its
 * nodes (`screenNodes`: drawing-buffer pixels, `null` behind the camera)
 * and points along the links between them.
 */
export function armPoints(screenNodes, dpr = 1) {
  const nodes = (screenNodes ?? []).filter(Boolean).map(([x, y]) => [x / dpr, y / dpr]);
  return nodes.flatMap((p, k) => (k === 0 ? [p] : Array.from({ length: PER_LINK }, (_, i) => {
    const t = (i + 1) / PER_LINK;
    const q = nodes[k - 1];
    return [q[0] + t * (p[0] - q[0]), q[1] + t * (p[1] - q[1])];
  })));
}

/** How many of `points` (view pixels) the box `r` (page pixels) covers, the view at `v`. */
function covered(points, r, v) {
  return points.filter(([x, y]) => x >= r.left - v.left && x <= r.right - v.left && y >= r.top - v.top && y <= r.bottom - v.top).length;
}

/**
 * Puts `notices` (an element with `data-corner`) in the corner of `view`
 * that covers the fewest of `points`: the current one while it covers none.
 */
export function placeNotices(notices, view, points) {
  if (!notices.querySelector('.notice') || points.length === 0) return;
  const v = view.getBoundingClientRect();
  const now = notices.dataset.corner ?? CORNERS[0];
  notices.dataset.corner = now;
  if (covered(points, notices.getBoundingClientRect(), v) === 0) return;
  let best = { corner: now, count: Infinity };
  for (const corner of CORNERS) {
    notices.dataset.corner = corner;
    const count = covered(points, notices.getBoundingClientRect(), v);
    if (count < best.count) best = { corner, count };
    if (count === 0) break;
  }
  notices.dataset.corner = best.corner;
}

/**
 * Keeps the stage's `--notices-top` just under the stats box (the top-left
 * corner's notices go there), or at the top when the stats are hidden.
 */
export function followStats(stage, stats) {
  new ResizeObserver(() => {
    const below = stats.offsetParent ? stats.offsetTop + stats.offsetHeight + 4 : 0;
    stage.style.setProperty('--notices-top', below ? `${below}px` : '0.5rem');
  }).observe(stats);
}
