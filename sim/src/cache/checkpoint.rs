//! Checkpoints: a versioned, checksummed container around the world's saved state
//! (each model's state as bytes), from which an interrupted run resumes exactly as if
//! it had not stopped.

use std::path::{Path, PathBuf};

use crate::error::{Result, SimError};

const MAGIC: &[u8; 8] = b"PFCKPT02";

/// A checkpoint: where the run was and the world's state.
#[derive(Debug, Clone, PartialEq)]
pub struct Checkpoint {
    /// Ties the checkpoint to its resolved scene.
    pub scene_hash: u64,
    /// The last frame written before the checkpoint.
    pub frame: u64,
    /// Steps taken.
    pub steps: u64,
    /// Bonds broken so far.
    pub broken_bonds: u64,
    /// Simulation time (s).
    pub time: f64,
    /// The world's saved state.
    pub payload: Vec<u8>,
}

impl Checkpoint {
    /// The bytes on disk.
    pub fn encode(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.payload.len() + 64);
        out.extend_from_slice(MAGIC);
        for v in [self.scene_hash, self.frame, self.steps, self.broken_bonds] {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out.extend_from_slice(&self.time.to_le_bytes());
        out.extend_from_slice(&(self.payload.len() as u64).to_le_bytes());
        out.extend_from_slice(&self.payload);
        out
    }

    /// Reads a checkpoint file.
    pub fn read(path: &Path) -> Result<Checkpoint> {
        let bytes = std::fs::read(path).map_err(|e| SimError::io(path, e))?;
        let mut d = Decoder::new(&bytes, path);
        if bytes.get(..8) != Some(MAGIC.as_slice()) {
            return Err(d.invalid("not a perifrac checkpoint".into()));
        }
        d.at = 8;
        let scene_hash = d.take_u64("header")?;
        let frame = d.take_u64("header")?;
        let steps = d.take_u64("header")?;
        let broken_bonds = d.take_u64("header")?;
        let time = d.take_f64("header")?;
        let len = d.take_u64("header")? as usize;
        if bytes.len() - d.at != len {
            return Err(d.invalid(format!(
                "the payload is {} bytes where the header says {len}",
                bytes.len() - d.at
            )));
        }
        Ok(Checkpoint {
            scene_hash,
            frame,
            steps,
            broken_bonds,
            time,
            payload: bytes[d.at..].to_vec(),
        })
    }
}

/// Writes a checkpoint payload.
#[derive(Debug, Default)]
pub struct Encoder {
    /// The bytes so far.
    pub bytes: Vec<u8>,
}

impl Encoder {
    /// A u64.
    pub fn put_u64(&mut self, v: u64) {
        self.bytes.extend_from_slice(&v.to_le_bytes());
    }
    /// An f64.
    pub fn put_f64(&mut self, v: f64) {
        self.bytes.extend_from_slice(&v.to_le_bytes());
    }
    /// f64 values.
    pub fn put_f64s(&mut self, v: &[f64]) {
        v.iter().for_each(|&x| self.put_f64(x));
    }
    /// 3-vectors.
    pub fn put_f64x3s(&mut self, v: &[[f64; 3]]) {
        v.iter().for_each(|x| self.put_f64s(x));
    }
    /// u32 values.
    pub fn put_u32s(&mut self, v: &[u32]) {
        v.iter()
            .for_each(|x| self.bytes.extend_from_slice(&x.to_le_bytes()));
    }
}

/// Reads a checkpoint payload, naming the file and the field on every failure.
#[derive(Debug)]
pub struct Decoder<'a> {
    bytes: &'a [u8],
    at: usize,
    path: PathBuf,
}

impl<'a> Decoder<'a> {
    /// A decoder over the payload of the checkpoint at `path`.
    pub fn new(bytes: &'a [u8], path: &Path) -> Decoder<'a> {
        Decoder {
            bytes,
            at: 0,
            path: path.to_path_buf(),
        }
    }
    /// An error about this checkpoint.
    pub fn invalid(&self, message: String) -> SimError {
        SimError::Cache {
            path: self.path.clone(),
            message,
        }
    }
    fn take<const N: usize>(&mut self, what: &str) -> Result<[u8; N]> {
        let s = self
            .bytes
            .get(self.at..self.at + N)
            .ok_or_else(|| self.invalid(format!("checkpoint is truncated in the {what}")))?;
        self.at += N;
        let mut a = [0u8; N];
        a.copy_from_slice(s);
        Ok(a)
    }
    /// A u64.
    pub fn take_u64(&mut self, what: &str) -> Result<u64> {
        Ok(u64::from_le_bytes(self.take(what)?))
    }
    /// An f64.
    pub fn take_f64(&mut self, what: &str) -> Result<f64> {
        Ok(f64::from_le_bytes(self.take(what)?))
    }
    /// A count that must equal `expected`.
    pub fn expect_count(&mut self, what: &str, expected: usize) -> Result<()> {
        let n = self.take_u64(what)?;
        if n != expected as u64 {
            return Err(self.invalid(format!(
                "checkpoint has {n} {what} where the scene gives {expected}"
            )));
        }
        Ok(())
    }
    /// f64 values into `out`.
    pub fn take_f64s_into(&mut self, out: &mut [f64], what: &str) -> Result<()> {
        for x in out {
            *x = self.take_f64(what)?;
        }
        Ok(())
    }
    /// 3-vectors into `out`.
    pub fn take_f64x3s_into(&mut self, out: &mut [[f64; 3]], what: &str) -> Result<()> {
        for x in out {
            self.take_f64s_into(x, what)?;
        }
        Ok(())
    }
    /// u32 values into `out`.
    pub fn take_u32s_into(&mut self, out: &mut [u32], what: &str) -> Result<()> {
        for x in out {
            *x = u32::from_le_bytes(self.take(what)?);
        }
        Ok(())
    }
    /// Refuses bytes left over.
    pub fn finish(&self) -> Result<()> {
        if self.at != self.bytes.len() {
            return Err(self.invalid(format!(
                "{} bytes are left over after the state",
                self.bytes.len() - self.at
            )));
        }
        Ok(())
    }
}
