//! An anchor's `clamp` key: absent (a fixed box held over a body's end is clamped at the
//! face where it meets the body, found at set-up: docs/lattice.md, "The clamp by
//! default"), `false` (the whole region held), or a plane `{ point, normal }`.

use std::fmt;

use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde::ser::Serializer;
use serde::{Deserialize, Serialize};

use super::exact;

/// The `clamp` key of an anchor, when given (see [`super::AnchorSpec::clamp`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Clamp {
    /// `clamp = false`: every particle of the region held at the anchor's motion, no
    /// clamp at its face (the anchor before issue 33; a clamp about λ/2 inside the
    /// face, and softer by an O(δ) boundary layer).
    Held,
    /// `clamp = { point, normal }`: a clamp at that plane.
    Plane(ClampSpec),
}

/// `clamp = { point, normal }` of an anchor: the clamp's plane, through `point`, with
/// `normal` pointing out of the clamp into the free body.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClampSpec {
    /// A point of the plane (m).
    #[serde(deserialize_with = "exact::array")]
    pub point: [f64; 3],
    /// The plane's normal, into the free body (any non-zero length).
    #[serde(deserialize_with = "exact::array")]
    pub normal: [f64; 3],
}

impl Serialize for Clamp {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            Clamp::Held => serializer.serialize_bool(false),
            Clamp::Plane(plane) => plane.serialize(serializer),
        }
    }
}

impl<'de> Deserialize<'de> for Clamp {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Clamp, D::Error> {
        deserializer.deserialize_any(ClampVisitor)
    }
}

/// Reads `false` or a table; `true` is refused with what to write instead (the face
/// clamp is already the default where it applies).
struct ClampVisitor;

impl<'de> Visitor<'de> for ClampVisitor {
    type Value = Clamp;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(
            "false (the whole region held) or a plane { point = [x, y, z], normal = [x, y, z] }",
        )
    }

    fn visit_bool<E: de::Error>(self, value: bool) -> Result<Clamp, E> {
        if value {
            return Err(E::custom(
                "clamp = true is not a setting: a fixed box region that meets a peridynamic \
                 body in one face is clamped at that face without it (`perifrac check` lists \
                 those anchors); write clamp = { point = [x, y, z], normal = [x, y, z] } for \
                 another plane, or clamp = false to hold the whole region",
            ));
        }
        Ok(Clamp::Held)
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Clamp, A::Error> {
        ClampSpec::deserialize(de::value::MapAccessDeserializer::new(map)).map(Clamp::Plane)
    }
}
