//! The rigid phase in a checkpoint: its pieces, the colliders it mirrors, the fragments
//! settling, the pieces' last contact forces and rapier's whole state, as CBOR (JSON
//! cannot hold rapier's tuple-keyed maps).

use std::collections::BTreeMap;

use rapier3d_f64::prelude::*;

use super::{Hold, Physics, Piece, RigidPhase};
use crate::cache::checkpoint::{Decoder, Encoder};
use crate::error::Result;
use crate::world::Part;

impl RigidPhase {
    /// Writes the rigid phase (its pieces, the colliders it mirrors, the fragments
    /// settling, the pieces' last contact forces, the points back in their models
    /// whose hit is not over and rapier's state) into a checkpoint.
    pub fn save(&self, out: &mut Encoder) {
        let state = (
            &self.pieces,
            &self.mirrors,
            &self.calm,
            &self.contact,
            &self.holds,
            &self.physics,
        );
        let mut bytes = Vec::new();
        // Writing into memory fails only on a type serde cannot express, which
        // rapier's state is not: an empty record would then fail the resume, loudly.
        let _ = ciborium::into_writer(&state, &mut bytes);
        out.put_u64(bytes.len() as u64);
        out.put_u32_slice(&bytes_to_words(&bytes));
    }

    /// Restores what [`RigidPhase::save`] wrote and freezes the pieces' points in
    /// their models.
    pub fn restore(&mut self, input: &mut Decoder<'_>, parts: &mut [Part]) -> Result<()> {
        let len = input.take_u64("rigid phase")? as usize;
        if len > input.remaining() {
            return Err(input
                .error(
                    "rigid phase",
                    format!("{len} bytes, more than the file holds"),
                )
                .into());
        }
        let words = input.take_u32_slice("rigid phase", len.div_ceil(4))?;
        let bytes = words_to_bytes(&words, len);
        type State = (
            Vec<Piece>,
            Vec<(usize, RigidBodyHandle)>,
            BTreeMap<(u32, u32), f64>,
            Vec<([f64; 3], [f64; 3])>,
            Vec<Hold>,
            Physics,
        );
        let (pieces, mirrors, calm, contact, holds, physics): State =
            ciborium::from_reader(bytes.as_slice())
                .map_err(|e| input.error("rigid phase", format!("does not read: {e}")))?;
        for (k, piece) in pieces.iter().enumerate() {
            let part = parts.get_mut(piece.part as usize);
            let n = part.as_ref().map_or(0, |p| p.model.points().position.len());
            if part.is_none()
                || piece.points.len() != piece.local.len()
                || piece.points.iter().any(|&i| i as usize >= n)
                || physics.bodies.get(piece.body).is_none()
            {
                return Err(input
                    .error(
                        "rigid phase",
                        format!("piece {k} names points or a body the scene has not"),
                    )
                    .into());
            }
            if let Some(part) = part {
                part.model.freeze(&piece.points);
            }
        }
        if contact.len() != pieces.len()
            || contact
                .iter()
                .flat_map(|(f, t)| f.iter().chain(t))
                .any(|x| !x.is_finite())
        {
            return Err(input
                .error(
                    "rigid phase",
                    "the pieces' contact forces do not match the pieces",
                )
                .into());
        }
        if holds.iter().any(|h| {
            parts.get(h.part as usize).is_none_or(|p| {
                h.points
                    .iter()
                    .any(|&i| i as usize >= p.model.points().position.len())
            })
        }) {
            return Err(input
                .error(
                    "rigid phase",
                    "a held fragment names points the scene has not",
                )
                .into());
        }
        self.contact = contact;
        self.holds = holds;
        self.pieces = pieces;
        self.mirrors = mirrors;
        self.calm = calm;
        self.physics = physics;
        Ok(())
    }
}

fn bytes_to_words(bytes: &[u8]) -> Vec<u32> {
    bytes
        .chunks(4)
        .map(|c| {
            let mut w = [0u8; 4];
            w[..c.len()].copy_from_slice(c);
            u32::from_le_bytes(w)
        })
        .collect()
}

fn words_to_bytes(words: &[u32], len: usize) -> Vec<u8> {
    let mut out: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    out.truncate(len);
    out
}
