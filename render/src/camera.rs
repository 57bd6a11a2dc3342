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

    /// Frames `bounds` from `azimuth` at [`ELEVATION`] as tightly as the box allows:
    /// the camera looks at the box's centre from the nearest distance at which all
    /// eight corners project inside [`FIT_FILL`] of the image's half-width and
    /// half-height. A box fills the image where [`Camera::framing`]'s bounding sphere
    /// leaves it small in the middle.
    pub fn fit(bounds: &Bounds, aspect: f32, azimuth: f32) -> Camera {
        if bounds.is_empty() {
            return Camera::framing(bounds, aspect, azimuth);
        }
        let distance = fit_distance(bounds, aspect, view_direction(azimuth));
        Camera::at_distance(bounds, aspect, azimuth, distance)
    }

    /// The camera looking at the centre of `bounds` from `azimuth` at [`ELEVATION`],
    /// `distance` away.
    fn at_distance(bounds: &Bounds, aspect: f32, azimuth: f32, distance: f32) -> Camera {
        let (center, radius) = (bounds.center(), bounds.radius().max(1e-3));
        Camera {
            eye: add(center, scale(view_direction(azimuth), distance)),
            target: center,
            fov_y: FOV_Y,
            aspect,
            near: (distance - 2.0 * radius).max(distance * 0.02),
            far: distance + 60.0 * radius,
        }
    }

    /// `views` cameras around the vertical axis through the bounds' centre, the first
    /// at `azimuth`, all at one distance: the largest that [`Camera::fit`] needs over
    /// the views, so the subject keeps its size as it turns.
    pub fn turntable(bounds: &Bounds, aspect: f32, azimuth: f32, views: usize) -> Vec<Camera> {
        let azimuths: Vec<f32> = (0..views)
            .map(|i| azimuth + std::f32::consts::TAU * i as f32 / views as f32)
            .collect();
        if bounds.is_empty() {
            return azimuths
                .into_iter()
                .map(|a| Camera::framing(bounds, aspect, a))
                .collect();
        }
        let distance = azimuths
            .iter()
            .map(|&a| fit_distance(bounds, aspect, view_direction(a)))
            .fold(0.0, f32::max);
        azimuths
            .into_iter()
            .map(|a| Camera::at_distance(bounds, aspect, a, distance))
            .collect()
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

/// The smallest distance from the centre of `bounds` along `back` (unit, towards the
/// eye) at which every corner of the box projects within [`FIT_FILL`] of the image:
/// a corner at (x, y, z) in the camera's right, up and backward axes about the centre
/// is in view when |x| ≤ FIT_FILL · tan(fov_x / 2) · (D − z), and likewise for y.
fn fit_distance(bounds: &Bounds, aspect: f32, back: [f32; 3]) -> f32 {
    let right = normalize(cross([0.0, 1.0, 0.0], back));
    let up = cross(back, right);
    let tan_y = FIT_FILL * (0.5 * FOV_Y).tan();
    let tan_x = aspect * tan_y;
    let center = bounds.center();
    let mut distance = 1e-3f32;
    for i in 0..8 {
        let corner = [
            if i & 1 == 0 {
                bounds.min[0]
            } else {
                bounds.max[0]
            },
            if i & 2 == 0 {
                bounds.min[1]
            } else {
                bounds.max[1]
            },
            if i & 4 == 0 {
                bounds.min[2]
            } else {
                bounds.max[2]
            },
        ];
        let d = sub(corner, center);
        let (x, y, z) = (dot(d, right), dot(d, up), dot(d, back));
        distance = distance.max(z + x.abs() / tan_x).max(z + y.abs() / tan_y);
    }
    distance
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

    #[test]
    fn framing_keeps_the_bounds_in_view() {
        for aspect in [0.5, 4.0 / 3.0, 16.0 / 9.0, 3.0] {
            for cam in Camera::turntable(&bounds(), aspect, AZIMUTH, 7) {
                let vp = cam.view_projection();
                let b = bounds();
                for i in 0..8 {
                    let p = [
                        if i & 1 == 0 { b.min[0] } else { b.max[0] },
                        if i & 2 == 0 { b.min[1] } else { b.max[1] },
                        if i & 4 == 0 { b.min[2] } else { b.max[2] },
                    ];
                    let c = transform(&vp, p);
                    for k in 0..3 {
                        assert!((c[k] / c[3]).abs() < 1.0, "{aspect} {p:?} {c:?}");
                    }
                }
                // The centre projects to the middle of the image.
                let c = transform(&vp, b.center());
                assert!((c[0] / c[3]).abs() < 1e-5 && (c[1] / c[3]).abs() < 1e-5);
            }
        }
    }

    #[test]
    fn fit_keeps_the_box_in_view_and_fills_it() {
        let b = bounds();
        for aspect in [0.5, 4.0 / 3.0, 16.0 / 9.0, 3.0] {
            for cam in Camera::turntable(&b, aspect, AZIMUTH, 5)
                .into_iter()
                .chain([Camera::fit(&b, aspect, AZIMUTH)])
            {
                let vp = cam.view_projection();
                // Every corner in view; the largest |x| or |y| reaches FIT_FILL.
                let mut largest = 0.0f32;
                for i in 0..8 {
                    let p = [
                        if i & 1 == 0 { b.min[0] } else { b.max[0] },
                        if i & 2 == 0 { b.min[1] } else { b.max[1] },
                        if i & 4 == 0 { b.min[2] } else { b.max[2] },
                    ];
                    let c = transform(&vp, p);
                    for k in 0..3 {
                        assert!((c[k] / c[3]).abs() < 1.0, "{aspect} {p:?} {c:?}");
                    }
                    largest = largest.max((c[0] / c[3]).abs()).max((c[1] / c[3]).abs());
                }
                // Turntable views share the distance the widest view needs.
                assert!(
                    largest > 0.5,
                    "{aspect}: the box reaches {largest} of the image"
                );
            }
            // Closer than the bounding sphere's framing.
            let fit = Camera::fit(&b, aspect, AZIMUTH);
            let sphere = Camera::framing(&b, aspect, AZIMUTH);
            assert!(norm(sub(fit.eye, fit.target)) < norm(sub(sphere.eye, sphere.target)));
        }
        // The single view reaches FIT_FILL exactly on its limiting side.
        let cam = Camera::fit(&b, 16.0 / 9.0, AZIMUTH);
        let vp = cam.view_projection();
        let reach = (0..8)
            .map(|i| {
                let p = [
                    if i & 1 == 0 { b.min[0] } else { b.max[0] },
                    if i & 2 == 0 { b.min[1] } else { b.max[1] },
                    if i & 4 == 0 { b.min[2] } else { b.max[2] },
                ];
                let c = transform(&vp, p);
                (c[0] / c[3]).abs().max((c[1] / c[3]).abs())
            })
            .fold(0.0f32, f32::max);
        assert!((reach - FIT_FILL).abs() < 1e-3, "{reach}");
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
