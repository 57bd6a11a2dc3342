//! Cameras: automatic framing from a scene's bounds (one fixed camera for a whole
//! sequence), turntable views around the vertical axis, and the studio lights placed
//! relative to the camera. Column-major 4×4 matrices, y up, right-handed, OpenGL clip
//! space.

use perifrac_math::{add, cross, dot, norm, normalize, scale, sub};

/// A column-major 4×4 matrix (`m[column][row]`), as GL takes it.
pub type Mat4 = [[f32; 4]; 4];

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Smallest corner.
    pub min: [f32; 3],
    /// Largest corner.
    pub max: [f32; 3],
}

impl Bounds {
    /// The empty box (grows from the first point added).
    pub const EMPTY: Bounds = Bounds {
        min: [f32::INFINITY; 3],
        max: [f32::NEG_INFINITY; 3],
    };

    /// Whether nothing was added.
    pub fn is_empty(&self) -> bool {
        (0..3).any(|k| self.min[k] > self.max[k])
    }

    /// Grows the box to hold `p` (non-finite points are ignored).
    pub fn add(&mut self, p: [f32; 3]) {
        if p.iter().all(|v| v.is_finite()) {
            self.min = std::array::from_fn(|k| self.min[k].min(p[k]));
            self.max = std::array::from_fn(|k| self.max[k].max(p[k]));
        }
    }

    /// The union of two boxes.
    pub fn union(&self, other: &Bounds) -> Bounds {
        let mut b = *self;
        if !other.is_empty() {
            b.add(other.min);
            b.add(other.max);
        }
        b
    }

    /// Centre.
    pub fn center(&self) -> [f32; 3] {
        std::array::from_fn(|k| 0.5 * (self.min[k] + self.max[k]))
    }

    /// Radius of the bounding sphere about the centre.
    pub fn radius(&self) -> f32 {
        0.5 * norm(sub(self.max, self.min))
    }
}

/// Where the camera is and what it sees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: [f32; 3],
    /// The point looked at.
    pub target: [f32; 3],
    /// Vertical field of view (radians).
    pub fov_y: f32,
    /// Width / height.
    pub aspect: f32,
    /// Near plane distance.
    pub near: f32,
    /// Far plane distance.
    pub far: f32,
}

/// Default vertical field of view: 30°, a "product shot" lens.
pub const FOV_Y: f32 = 30.0 * std::f32::consts::PI / 180.0;
/// Azimuth of the default view, from +z towards +x (radians): front-right.
pub const AZIMUTH: f32 = 35.0 * std::f32::consts::PI / 180.0;
/// Elevation of the default view above the horizon (radians).
pub const ELEVATION: f32 = 22.0 * std::f32::consts::PI / 180.0;

impl Camera {
    /// Frames `bounds` from `azimuth` (radians about +y, 0 looks from +z) at
    /// [`ELEVATION`]: the bounding sphere fits the narrower field of view with a margin.
    pub fn framing(bounds: &Bounds, aspect: f32, azimuth: f32) -> Camera {
        let (center, radius) = if bounds.is_empty() {
            ([0.0; 3], 1.0)
        } else {
            (bounds.center(), bounds.radius().max(1e-3))
        };
        let half_fov = (0.5 * FOV_Y).min((aspect * (0.5 * FOV_Y).tan()).atan());
        let distance = 1.1 * radius / half_fov.sin();
        let dir = [
            ELEVATION.cos() * azimuth.sin(),
            ELEVATION.sin(),
            ELEVATION.cos() * azimuth.cos(),
        ];
        Camera {
            eye: add(center, scale(dir, distance)),
            target: center,
            fov_y: FOV_Y,
            aspect,
            near: (distance - 2.0 * radius).max(distance * 0.02),
            far: distance + 60.0 * radius,
        }
    }

    /// Frames `subject` from `azimuth` at [`ELEVATION`] as tightly as it allows: the
    /// nearest eye from which the subject projects inside [`FIT_FILL`] of the image,
    /// centred on its projection (see [`Subject`]). `bounds` (the subject's box) sets
    /// the look-at depth and the clip planes. An empty subject falls back to
    /// [`Camera::framing`].
    pub fn fit(subject: &Subject, bounds: &Bounds, aspect: f32, azimuth: f32) -> Camera {
        match FrustumFit::new(subject, aspect, azimuth) {
            Some(fit) => fit.camera(fit.depth, bounds, aspect),
            None => Camera::framing(bounds, aspect, azimuth),
        }
    }

    /// `views` cameras around the vertical axis, the first at `azimuth`, each centred
    /// on the subject as [`Camera::fit`] centres it, all at one depth: the largest that
    /// a view needs, so the subject keeps its size as it turns.
    pub fn turntable(
        subject: &Subject,
        bounds: &Bounds,
        aspect: f32,
        azimuth: f32,
        views: usize,
    ) -> Vec<Camera> {
        let azimuths: Vec<f32> = (0..views)
            .map(|i| azimuth + std::f32::consts::TAU * i as f32 / views as f32)
            .collect();
        let fits: Option<Vec<FrustumFit>> = azimuths
            .iter()
            .map(|&a| FrustumFit::new(subject, aspect, a))
            .collect();
        match fits {
            Some(fits) => {
                let depth = fits.iter().map(|f| f.depth).fold(f32::MIN, f32::max);
                fits.iter()
                    .map(|f| f.camera(depth, bounds, aspect))
                    .collect()
            }
            None => azimuths
                .into_iter()
                .map(|a| Camera::framing(bounds, aspect, a))
                .collect(),
        }
    }

    /// Unit vector from the target to the eye.
    pub fn backward(&self) -> [f32; 3] {
        normalize(sub(self.eye, self.target))
    }

    /// Unit right vector of the image.
    pub fn right(&self) -> [f32; 3] {
        normalize(cross([0.0, 1.0, 0.0], self.backward()))
    }

    /// Unit up vector of the image.
    pub fn up(&self) -> [f32; 3] {
        cross(self.backward(), self.right())
    }

    /// The view matrix (world → camera).
    pub fn view(&self) -> Mat4 {
        look_at(self.eye, self.right(), self.up(), self.backward())
    }

    /// The perspective projection.
    pub fn projection(&self) -> Mat4 {
        let f = 1.0 / (0.5 * self.fov_y).tan();
        let (n, far) = (self.near, self.far);
        [
            [f / self.aspect, 0.0, 0.0, 0.0],
            [0.0, f, 0.0, 0.0],
            [0.0, 0.0, (far + n) / (n - far), -1.0],
            [0.0, 0.0, 2.0 * far * n / (n - far), 0.0],
        ]
    }

    /// Projection × view.
    pub fn view_projection(&self) -> Mat4 {
        mul(&self.projection(), &self.view())
    }

    /// The studio lights for this camera, as unit directions towards each light, in
    /// world space: key above-left-front of the camera, fill low on the right, rim
    /// behind the subject. They turn with the camera, as a studio turntable's do.
    pub fn lights(&self) -> Lights {
        let (r, u, b) = (self.right(), [0.0, 1.0, 0.0], self.backward());
        let b_flat = normalize([b[0], 0.0, b[2]]);
        let dir = |x: f32, y: f32, z: f32| {
            normalize(add(add(scale(r, x), scale(u, y)), scale(b_flat, z)))
        };
        Lights {
            key: dir(-0.55, 1.0, 0.45),
            fill: dir(0.9, 0.35, 0.5),
            rim: dir(0.3, 0.6, -1.0),
        }
    }
}

/// The fraction of the image's half-width and half-height that [`Camera::fit`] lets
/// the framed box reach: a margin of 8 % on each side.
pub const FIT_FILL: f32 = 0.92;

/// Unit vector from the target towards the eye at `azimuth` and [`ELEVATION`].
fn view_direction(azimuth: f32) -> [f32; 3] {
    [
        ELEVATION.cos() * azimuth.sin(),
        ELEVATION.sin(),
        ELEVATION.cos() * azimuth.cos(),
    ]
}

/// What a camera frames: sample points of the bodies, of which the framing may leave
/// a small fraction out of the picture (far debris), and points it keeps whole (the
/// colliders, the projectile's path).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Subject {
    /// Points of the bodies (particles or surface vertices), pooled over the shot.
    pub samples: Vec<[f32; 3]>,
    /// How far the bodies reach past their sample points (half a particle).
    pub pad: f32,
    /// The fraction of `samples` whose quantile along each edge's normal sets how far
    /// out a sample counts as part of the subject (see `Subject::support`).
    pub tail: f32,
    /// Points always in the picture.
    pub whole: Vec<[f32; 3]>,
}

impl Subject {
    /// A subject of `points`, all of them in the picture.
    pub fn whole(points: Vec<[f32; 3]>) -> Subject {
        Subject {
            whole: points,
            ..Subject::default()
        }
    }

    /// How far the subject reaches along `n`: the largest `p · n` of the whole points
    /// and of the samples (plus the pad), leaving out far outliers. `None` for a
    /// subject with no finite point.
    ///
    /// A sample is an outlier when it lies beyond the `tail` quantile along `n` by more
    /// than [`OUTLIER_SPREAD`] of the samples' spread between the two `tail` quantiles:
    /// a grain flung far off is left out, while the feet of a figure or the edge of a
    /// sheet, attached to the subject but fewer than `tail` of its points, stay in.
    fn support(&self, n: [f32; 3]) -> Option<f32> {
        let finite = |p: &&[f32; 3]| p.iter().all(|v| v.is_finite());
        let whole = self
            .whole
            .iter()
            .filter(finite)
            .map(|&p| dot(p, n))
            .reduce(f32::max);
        let mut values: Vec<f32> = self
            .samples
            .iter()
            .filter(finite)
            .map(|&p| dot(p, n))
            .collect();
        let sampled = (!values.is_empty()).then(|| {
            let cut = ((values.len() as f32 * self.tail) as usize).min((values.len() - 1) / 2);
            let last = values.len() - 1 - cut;
            let high = *values.select_nth_unstable_by(last, f32::total_cmp).1;
            let low = *values.select_nth_unstable_by(cut, f32::total_cmp).1;
            let reach = high + OUTLIER_SPREAD * (high - low);
            let kept = values
                .iter()
                .copied()
                .filter(|&v| v <= reach)
                .fold(high, f32::max);
            kept + self.pad * norm(n)
        });
        match (whole, sampled) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        }
    }
}

/// How far beyond its `tail` quantile, as a fraction of the spread between the two
/// quantiles, a sample still counts as part of the subject (see `Subject::support`).
pub const OUTLIER_SPREAD: f32 = 0.25;

/// The tightest eye for a subject seen along a fixed direction, in the camera's axes.
///
/// A point p is in view when it lies inside the four planes of the frustum narrowed to
/// [`FIT_FILL`]. With t = FIT_FILL · tan(fov / 2) on each axis, the right plane's
/// condition (p − e) · (r + tₓ b) ≤ 0 reads e · (r + tₓ b) ≥ h₊ₓ, where h₊ₓ is the
/// subject's support along r + tₓ b, and likewise for the left, top and bottom planes.
/// Writing e = eᵣ r + eᵤ u + e_b b, the right and left planes give
/// e_b ≥ (h₊ₓ + h₋ₓ) / (2 tₓ) and centre eᵣ = (h₊ₓ − h₋ₓ) / 2; the top and bottom the
/// same in y. The nearest eye takes the larger depth; on the axis that sets it the
/// subject touches both edges, on the other it sits in the middle.
struct FrustumFit {
    right: [f32; 3],
    up: [f32; 3],
    back: [f32; 3],
    /// eᵣ and eᵤ.
    offset: [f32; 2],
    /// e_b, the least depth along `back` that keeps the subject in view.
    depth: f32,
}

impl FrustumFit {
    fn new(subject: &Subject, aspect: f32, azimuth: f32) -> Option<FrustumFit> {
        let back = view_direction(azimuth);
        let right = normalize(cross([0.0, 1.0, 0.0], back));
        let up = cross(back, right);
        let tan_y = FIT_FILL * (0.5 * FOV_Y).tan();
        let tan_x = aspect * tan_y;
        let reach = |axis: [f32; 3], t: f32| -> Option<(f32, f32)> {
            let plus = subject.support(add(axis, scale(back, t)))?;
            let minus = subject.support(add(scale(axis, -1.0), scale(back, t)))?;
            Some(((plus + minus) / (2.0 * t), 0.5 * (plus - minus)))
        };
        let (depth_x, e_r) = reach(right, tan_x)?;
        let (depth_y, e_u) = reach(up, tan_y)?;
        Some(FrustumFit {
            right,
            up,
            back,
            offset: [e_r, e_u],
            depth: depth_x.max(depth_y),
        })
    }

    /// The camera at `depth` (at least [`FrustumFit::depth`]) looking along −`back`
    /// at the point of its axis level with the centre of `bounds`.
    fn camera(&self, depth: f32, bounds: &Bounds, aspect: f32) -> Camera {
        let eye = add(
            add(
                scale(self.right, self.offset[0]),
                scale(self.up, self.offset[1]),
            ),
            scale(self.back, depth),
        );
        let (center, radius) = if bounds.is_empty() {
            (scale(self.back, depth - 1.0), 1.0)
        } else {
            (bounds.center(), bounds.radius().max(1e-3))
        };
        let distance = dot(sub(eye, center), self.back).max(1e-3);
        Camera {
            eye,
            target: sub(eye, scale(self.back, distance)),
            fov_y: FOV_Y,
            aspect,
            near: (distance - 2.0 * radius).max(distance * 0.02),
            far: distance + 60.0 * radius,
        }
    }
}

/// Directions towards the three studio lights (unit, world space).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lights {
    /// The key light (casts the shadow).
    pub key: [f32; 3],
    /// The fill light.
    pub fill: [f32; 3],
    /// The rim light, from behind.
    pub rim: [f32; 3],
}

/// The key light's orthographic view-projection covering the sphere (`center`,
/// `radius`): what the shadow map sees.
pub fn shadow_view_projection(key: [f32; 3], center: [f32; 3], radius: f32) -> Mat4 {
    let back = normalize(key);
    let helper = if back[1].abs() > 0.99 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let right = normalize(cross(helper, back));
    let up = cross(back, right);
    let eye = add(center, scale(back, 2.0 * radius));
    let view = look_at(eye, right, up, back);
    let (n, f) = (0.0, 4.0 * radius);
    let ortho = [
        [1.0 / radius, 0.0, 0.0, 0.0],
        [0.0, 1.0 / radius, 0.0, 0.0],
        [0.0, 0.0, -2.0 / (f - n), 0.0],
        [0.0, 0.0, -(f + n) / (f - n), 1.0],
    ];
    mul(&ortho, &view)
}

fn look_at(eye: [f32; 3], right: [f32; 3], up: [f32; 3], back: [f32; 3]) -> Mat4 {
    [
        [right[0], up[0], back[0], 0.0],
        [right[1], up[1], back[1], 0.0],
        [right[2], up[2], back[2], 0.0],
        [-dot(right, eye), -dot(up, eye), -dot(back, eye), 1.0],
    ]
}

/// `a × b` for column-major matrices.
pub fn mul(a: &Mat4, b: &Mat4) -> Mat4 {
    std::array::from_fn(|c| std::array::from_fn(|r| (0..4).map(|k| a[k][r] * b[c][k]).sum()))
}

/// `m · (p, 1)`.
pub fn transform(m: &Mat4, p: [f32; 3]) -> [f32; 4] {
    std::array::from_fn(|r| m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bounds() -> Bounds {
        Bounds {
            min: [-0.2, 0.0, -0.1],
            max: [0.2, 0.4, 0.1],
        }
    }

    fn corners(b: &Bounds) -> Vec<[f32; 3]> {
        (0..8)
            .map(|i| {
                std::array::from_fn(|k| {
                    if i & (1 << k) == 0 {
                        b.min[k]
                    } else {
                        b.max[k]
                    }
                })
            })
            .collect()
    }

    /// Where `p` lands in normalized device coordinates.
    fn ndc(cam: &Camera, p: [f32; 3]) -> [f32; 3] {
        let c = transform(&cam.view_projection(), p);
        [c[0] / c[3], c[1] / c[3], c[2] / c[3]]
    }

    #[test]
    fn framing_keeps_the_bounds_in_view() {
        let b = bounds();
        for aspect in [0.5, 4.0 / 3.0, 16.0 / 9.0, 3.0] {
            let cam = Camera::framing(&b, aspect, AZIMUTH);
            for p in corners(&b) {
                assert!(ndc(&cam, p).iter().all(|v| v.abs() < 1.0), "{aspect} {p:?}");
            }
            // The centre projects to the middle of the image.
            let c = ndc(&cam, b.center());
            assert!(c[0].abs() < 1e-5 && c[1].abs() < 1e-5);
        }
    }

    #[test]
    fn fit_touches_both_edges_of_its_limiting_axis_and_centres_the_other() {
        let b = bounds();
        let subject = Subject::whole(corners(&b));
        for aspect in [0.5, 4.0 / 3.0, 16.0 / 9.0, 3.0] {
            for azimuth in [0.0, AZIMUTH, 2.0, 4.0] {
                let cam = Camera::fit(&subject, &b, aspect, azimuth);
                let (mut lo, mut hi) = ([f32::MAX; 2], [f32::MIN; 2]);
                for p in corners(&b) {
                    let c = ndc(&cam, p);
                    assert!(c.iter().all(|v| v.abs() < 1.0), "{aspect} {p:?} {c:?}");
                    for k in 0..2 {
                        lo[k] = lo[k].min(c[k]);
                        hi[k] = hi[k].max(c[k]);
                    }
                }
                // One axis spans exactly ±FIT_FILL; the other lies within it, about
                // the middle.
                let limiting = (0..2)
                    .find(|&k| (hi[k] - FIT_FILL).abs() < 1e-3 && (lo[k] + FIT_FILL).abs() < 1e-3);
                let k = limiting.unwrap_or_else(|| panic!("{aspect} {azimuth}: {lo:?} {hi:?}"));
                let other = 1 - k;
                assert!(hi[other] <= FIT_FILL + 1e-4 && lo[other] >= -FIT_FILL - 1e-4);
                assert!(
                    (hi[other] + lo[other]).abs() < 0.25 * (hi[other] - lo[other]),
                    "{aspect} {azimuth}: {lo:?} {hi:?}"
                );
                // Closer than the bounding sphere's framing.
                let sphere = Camera::framing(&b, aspect, azimuth);
                assert!(norm(sub(cam.eye, b.center())) < norm(sub(sphere.eye, b.center())));
            }
        }
    }

    #[test]
    fn fit_leaves_out_far_debris_but_keeps_whole_points() {
        // 1000 points on a unit square and 5 debris points far to the right.
        let mut samples: Vec<[f32; 3]> = (0..1000)
            .map(|i| [(i % 40) as f32 / 40.0, (i / 40) as f32 / 25.0, 0.0])
            .collect();
        samples.extend((0..5).map(|i| [20.0 + i as f32, 0.5, 0.0]));
        samples.push([f32::NAN, 0.0, 0.0]);
        let b = Bounds {
            min: [0.0; 3],
            max: [1.0, 1.0, 0.0],
        };
        let mut subject = Subject {
            samples,
            tail: 0.01,
            ..Subject::default()
        };
        // A foot of 4 points just past the body (under 1 % of the points) stays in.
        subject
            .samples
            .extend((0..4).map(|i| [1.15, 0.1 * i as f32, 0.0]));
        let cam = Camera::fit(&subject, &b, 1.5, 0.0);
        for p in subject.samples[..1000]
            .iter()
            .chain(&subject.samples[1006..])
        {
            let c = ndc(&cam, *p);
            assert!(c.iter().all(|v| v.abs() < 1.0), "{p:?}: {c:?}");
        }
        assert!(
            ndc(&cam, [20.0, 0.5, 0.0])[0] > 1.0,
            "the debris is left out"
        );
        // A whole point far out is kept in the picture.
        let mut kept = subject.clone();
        kept.whole.push([20.0, 0.5, 0.0]);
        let cam = Camera::fit(&kept, &b, 1.5, 0.0);
        assert!(ndc(&cam, [20.0, 0.5, 0.0])[0] < 1.0);
        // Nothing to frame: the bounding sphere's view.
        let empty = Subject::default();
        assert_eq!(
            Camera::fit(&empty, &b, 1.5, 0.0),
            Camera::framing(&b, 1.5, 0.0)
        );
    }

    #[test]
    fn turntable_views_share_one_depth_and_keep_the_subject_in_view() {
        let b = bounds();
        let subject = Subject::whole(corners(&b));
        let views = Camera::turntable(&subject, &b, 16.0 / 9.0, AZIMUTH, 7);
        assert_eq!(views.len(), 7);
        let depth = |c: &Camera| dot(c.eye, c.backward());
        for cam in &views {
            assert!((depth(cam) - depth(&views[0])).abs() < 1e-4);
            for p in corners(&b) {
                assert!(ndc(cam, p).iter().all(|v| v.abs() < 1.0));
            }
        }
        assert_eq!(
            views[0].backward(),
            Camera::fit(&subject, &b, 16.0 / 9.0, AZIMUTH).backward()
        );
    }

    #[test]
    fn shadow_projection_covers_the_sphere() {
        let b = bounds();
        let cam = Camera::framing(&b, 1.5, AZIMUTH);
        let m = shadow_view_projection(cam.lights().key, b.center(), b.radius());
        for p in [b.min, b.max, b.center()] {
            let c = transform(&m, p);
            assert!(c.iter().take(3).all(|v| v.abs() <= 1.0 + 1e-5), "{c:?}");
        }
    }
}
