//! Sources and sinks of a membrane's diffused quantity θ: the S of Han Eq. 8 and 25,
//! placed in the scene (`[[body.membrane.source]]`) on a region of the sheet or on
//! spots scattered over it with the scene's `seed`.
//!
//! Departure from Eq. 25 as printed, where S_i sits inside the sum over j next to the
//! conduction term and is multiplied by W_ij A_j: that makes a source's strength
//! depend on how many neighbours its particle has (weaker at an edge, stronger with a
//! larger cutoff R). Here a source adds S_i/(ρC) = `rate` to θ̇_i directly — Eq. 8 with
//! S = ρ C × rate per unit volume — so `rate` is what the artist sees: θ per second.
//! A `value` source holds θ at a value instead (a reservoir, or an absorbing sink at 0).

use perifrac_math::{SplitMix64, dist};

use crate::error::{Result, SimError};
use crate::geometry::shape::to_sdf;
use crate::scene::Scene;

/// What a source does to θ on its particles while it is active.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Effect {
    /// θ̇ += rate (units of θ per second; negative is a sink).
    Rate(f64),
    /// θ held at the value.
    Value(f64),
}

/// One source or sink, resolved to the particles it acts on.
#[derive(Debug, Clone, PartialEq)]
pub struct Source {
    /// Particles it acts on, in increasing order.
    pub particles: Vec<u32>,
    /// What it does.
    pub effect: Effect,
    /// Time (s) at which it starts.
    pub start: f64,
    /// Time (s) after which it stops.
    pub until: f64,
}

impl Source {
    /// Whether it acts during the step that starts at `time`.
    pub fn active(&self, time: f64) -> bool {
        self.start <= time && time < self.until
    }
}

/// The sources of every membrane body of `scene` on the particles at `reference` of
/// bodies `body`: a source's region (default: its whole sheet) holds the particles of
/// its body inside it; a scattered source draws `count` of those particles with the
/// scene's seed (one generator for the scene, drawn in body and source order) and acts
/// on the particles of the region within `radius` of each.
pub fn of_scene(scene: &Scene, reference: &[[f64; 3]], body: &[u32]) -> Result<Vec<Source>> {
    let mut rng = SplitMix64::new(scene.scene.seed);
    let mut sources = Vec::new();
    for (b, spec) in scene.bodies.iter().enumerate() {
        let Some(membrane) = &spec.membrane else {
            continue;
        };
        let on_body = (0..reference.len() as u32).filter(|&i| body[i as usize] == b as u32);
        for (k, source) in membrane.sources.iter().enumerate() {
            let where_ = |message: String| SimError::Mesh {
                body: spec.name.clone(),
                message: format!("[[body.membrane.source]] {}: {message}", k + 1),
            };
            let inside: Vec<u32> = match &source.region {
                Some(region) => {
                    let sdf = to_sdf(region, &scene.base_dir).map_err(&where_)?;
                    on_body
                        .clone()
                        .filter(|&i| sdf.distance(reference[i as usize]) <= 0.0)
                        .collect()
                }
                None => on_body.clone().collect(),
            };
            if inside.is_empty() {
                return Err(where_(
                    "its region holds no particle of the sheet: move or enlarge it".into(),
                ));
            }
            let particles = match &source.scatter {
                None => inside,
                Some(scatter) => {
                    let centres: Vec<[f64; 3]> = (0..scatter.count)
                        .map(|_| reference[inside[rng.below(inside.len())] as usize])
                        .collect();
                    inside
                        .into_iter()
                        .filter(|&i| {
                            let x = reference[i as usize];
                            centres.iter().any(|&c| dist(x, c) <= scatter.radius)
                        })
                        .collect()
                }
            };
            let effect = match (source.rate, source.value) {
                (Some(rate), None) => Effect::Rate(rate),
                (None, Some(value)) => Effect::Value(value),
                _ => return Err(where_("give exactly one of rate and value".into())),
            };
            sources.push(Source {
                particles,
                effect,
                start: source.start,
                until: source.until,
            });
        }
    }
    Ok(sources)
}
