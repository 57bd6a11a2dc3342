//! The faces of cuts made before the first step, closed to the contact spring until
//! they come apart (module doc of [`super`], issue 33 item 7): finding them at set-up,
//! following which have opened, and keeping them in checkpoints.

use super::*;

impl ParticleContact {
    /// The faces of pre-existing cuts at set-up (module doc): pairs of one body with
    /// self-contact, no intact bond joining them, closer than [`PRECUT_RANGE`] mean
    /// spacings; (i, j) and (j, i), in increasing order.
    pub(super) fn precut_faces(&self, bonds: &[Option<&Bonds>]) -> Vec<(u32, u32)> {
        let n = self.len();
        let widest = self.spacing.iter().fold(0.0f64, |m, &l| m.max(l));
        let cell = PRECUT_RANGE * widest;
        if n == 0 || cell <= 0.0 {
            return Vec::new();
        }
        let key = |y: [f64; 3]| y.map(|x| (x / cell).floor() as i64);
        let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        for i in 0..n {
            if self.self_contact[self.part[i] as usize] {
                cells
                    .entry(key(self.reference[i]))
                    .or_default()
                    .push(i as u32);
            }
        }
        let lists: Vec<Vec<(u32, u32)>> = (0..n)
            .into_par_iter()
            .with_min_len(256)
            .map(|i| {
                let mut out = Vec::new();
                let part = self.part[i] as usize;
                if !self.self_contact[part] {
                    return out;
                }
                let c = key(self.reference[i]);
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        for dz in -1..=1 {
                            let Some(list) = cells.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                                continue;
                            };
                            for &j in list {
                                let j = j as usize;
                                if j == i
                                    || self.part[j] as usize != part
                                    || self.body[j] != self.body[i]
                                {
                                    continue;
                                }
                                let xi = sub(self.reference[i], self.reference[j]);
                                let range =
                                    PRECUT_RANGE * 0.5 * (self.spacing[i] + self.spacing[j]);
                                if dot(xi, xi) >= range * range {
                                    continue;
                                }
                                let intact = bonds[part].is_some_and(|b| {
                                    let local = |x: usize| x - self.offsets[part];
                                    [
                                        bond_index(b, local(i), local(j)),
                                        bond_index(b, local(j), local(i)),
                                    ]
                                    .iter()
                                    .any(|&k| {
                                        k != NO_BOND && b.neighbours[k as usize] & BROKEN == 0
                                    })
                                });
                                if !intact {
                                    out.push((i as u32, j as u32));
                                }
                            }
                        }
                    }
                }
                out.sort_unstable();
                out
            })
            .collect();
        lists.concat()
    }

    /// The closed faces still in the list, (i, j) in increasing order.
    pub(super) fn closed_in_list(&self) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        for i in 0..self.pair_offsets.len().saturating_sub(1) {
            for pair in &self.pairs[self.pair_offsets[i]..self.pair_offsets[i + 1]] {
                if pair.closed {
                    out.push((i as u32, pair.j));
                }
            }
        }
        out
    }

    /// Opens the closed faces now farther apart than their `open` distance. Each
    /// point updates its own pairs from the same positions, so i and j agree.
    pub(super) fn mark_opened(&mut self) {
        let position = &self.position;
        let mut rows = crate::family::rows_mut(&mut self.pairs, &self.pair_offsets);
        rows.par_iter_mut()
            .enumerate()
            .with_min_len(512)
            .for_each(|(i, row)| {
                for pair in row.iter_mut().filter(|p| p.closed) {
                    let d = sub(position[i], position[pair.j as usize]);
                    if dot(d, d) > pair.open * pair.open {
                        pair.closed = false;
                    }
                }
            });
    }

    /// Writes the closed faces (module doc): the state a resumed run needs.
    pub fn save(&self, out: &mut Encoder) {
        let closed = self.closed_in_list();
        out.put_u64(closed.len() as u64);
        let flat: Vec<u32> = closed.iter().flat_map(|&(i, j)| [i, j]).collect();
        out.put_u32_slice(&flat);
    }

    /// Reads what [`ParticleContact::save`] wrote, every pair checked to name two
    /// points of one body in increasing order; the next build takes it.
    pub fn restore(&mut self, input: &mut Decoder<'_>) -> Result<()> {
        let field = "particle contact: closed faces";
        let count = input.take_u64(field)?;
        let n = self.len() as u64;
        if count > n.saturating_mul(n) {
            return Err(input
                .error(field, format!("{count} pairs of {n} points"))
                .into());
        }
        let flat = input.take_u32_slice(field, 2 * count as usize)?;
        let pairs: Vec<(u32, u32)> = flat.chunks_exact(2).map(|c| (c[0], c[1])).collect();
        let bad = pairs.iter().enumerate().position(|(k, &(i, j))| {
            i as u64 >= n
                || j as u64 >= n
                || i == j
                || self.part[i as usize] != self.part[j as usize]
                || self.body[i as usize] != self.body[j as usize]
                || k > 0 && pairs[k - 1] >= (i, j)
        });
        if let Some(k) = bad {
            let message = format!(
                "pair {k}, {:?}, is not two points of one body in increasing order",
                pairs[k]
            );
            return Err(input.error(field, message).into());
        }
        self.closed = pairs;
        self.closed_known = true;
        self.restored = true;
        self.invalidate();
        Ok(())
    }
}
