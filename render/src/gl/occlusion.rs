//! The occlusion culling of the points' sphere impostors: only discs that can be seen
//! are drawn ([`visible_points`]).

use crate::camera::Mat4;
use crate::geometry::POINT_STRIDE;

/// Cell size (pixels) of the occlusion grid of [`visible_points`].
const CELL: f32 = 1.0;

/// The points that can be seen through `view_proj` on a `width`×`height` target, nearest
/// first, appended to `out` (interleaved, [`POINT_STRIDE`] floats each).
///
/// Impostors are flat discs at their centre's depth (no `gl_FragDepth`), so a disc is
/// hidden exactly where a disc with a nearer centre covers it. Going front to back over a
/// grid of `CELL`-pixel cells, a disc is kept unless every cell it overlaps is already
/// covered; a kept disc covers the cells that lie wholly inside it. This is
/// conservative (only wholly hidden discs are dropped), so the image is the same as
/// drawing all of them, while a dense block of particles shades only its outer layer
/// (llvmpipe cannot reject fragments early in a shader that discards). Ties keep the
/// input order, so the result is the same on every run.
pub(super) fn visible_points(
    points: &[f32],
    view_proj: &Mat4,
    pixels_per_unit: f32,
    perspective: bool,
    (width, height): (i32, i32),
    out: &mut Vec<f32>,
) {
    let (gw, gh) = (
        (width as f32 / CELL).ceil() as usize,
        (height as f32 / CELL).ceil() as usize,
    );
    // (depth key, index, centre x, centre y in cells, radius in cells)
    let mut order: Vec<(u32, u32, f32, f32, f32)> = points
        .chunks_exact(POINT_STRIDE)
        .enumerate()
        .filter_map(|(i, p)| {
            let c = crate::camera::transform(view_proj, [p[0], p[1], p[2]]);
            let w = if perspective { c[3] } else { 1.0 };
            if w.is_nan() || w <= 0.0 || !c.iter().all(|v| v.is_finite()) {
                return None;
            }
            let (x, y, z) = (c[0] / c[3], c[1] / c[3], c[2] / c[3]);
            let r = p[3] * pixels_per_unit / w / CELL;
            let (cx, cy) = (
                (x * 0.5 + 0.5) * width as f32 / CELL,
                (y * 0.5 + 0.5) * height as f32 / CELL,
            );
            let margin = r + 1.0;
            if !(-1.0..=1.0).contains(&z)
                || cx < -margin
                || cy < -margin
                || cx > gw as f32 + margin
                || cy > gh as f32 + margin
            {
                return None;
            }
            // Depth in [0, 2]: non-negative floats order like their bit patterns.
            Some(((z + 1.0).to_bits(), i as u32, cx, cy, r))
        })
        .collect();
    order.sort_unstable_by_key(|o| (o.0, o.1));
    let mut covered = vec![false; gw * gh];
    for (_, i, cx, cy, r) in order {
        let x0 = ((cx - r).floor().max(0.0) as usize).min(gw);
        let x1 = ((cx + r).ceil().max(0.0) as usize).min(gw);
        let y0 = ((cy - r).floor().max(0.0) as usize).min(gh);
        let y1 = ((cy + r).ceil().max(0.0) as usize).min(gh);
        // Hidden if every cell the disc overlaps (nearest point within r) is covered.
        let hidden = x0 < x1
            && y0 < y1
            && (y0..y1).all(|y| {
                let dy = (cy - cy.clamp(y as f32, y as f32 + 1.0)).abs();
                (x0..x1).all(|x| {
                    let dx = (cx - cx.clamp(x as f32, x as f32 + 1.0)).abs();
                    covered[y * gw + x] || dx * dx + dy * dy > r * r
                })
            });
        if hidden {
            continue;
        }
        let i = i as usize * POINT_STRIDE;
        out.extend_from_slice(&points[i..i + POINT_STRIDE]);
        // Cells wholly inside the disc: their farthest corner is within r.
        for y in y0..y1 {
            let dy = (y as f32 - cy).abs().max((y as f32 + 1.0 - cy).abs());
            for x in x0..x1 {
                let dx = (x as f32 - cx).abs().max((x as f32 + 1.0 - cx).abs());
                if dx * dx + dy * dy <= r * r {
                    covered[y * gw + x] = true;
                }
            }
        }
    }
}
