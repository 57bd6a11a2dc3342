//! Checkpoints: a versioned, checksummed container around the state a model saves,
//! from which an interrupted run resumes exactly as if it had not stopped.
//!
//! The container knows the clock and the run's counters; the model's state (positions,
//! velocities, bonds, …: what it needs, never scratch buffers) is an opaque payload
//! the model writes with an [`Encoder`] and reads back with a [`Decoder`].
//!
//! File layout, all little-endian:
//!
//! | bytes | field |
//! |---|---|
//! | 8 | magic `PFCKPT02` |
//! | 4 | format version (u32, [`FORMAT_VERSION`]) |
//! | 8 × 4 | scene hash, frame, steps, broken bonds (u64) |
//! | 8 | simulation time (f64) |
//! | 8 | payload length (u64) |
//! | n | payload |
//! | 4 | CRC-32 (IEEE) of every byte before it |
//!
//! In a payload a slice is its length (u64) and then its values, so a decoder checks
//! each array's length against the scene before reading it.

use std::io::{Seek, SeekFrom, Write};
use std::path::Path;

use crate::error::{CacheError, Result};

/// The first eight bytes of a checkpoint.
pub const MAGIC: &[u8; 8] = b"PFCKPT02";

/// Version of the layout after the magic: the container and the models' payloads
/// (2: the embedded mesh's crack-face set, for checkpoints taken during a frame; 3: the
/// crushed bonds' e^c of a crushing material; 5: particle contact's closed faces, after
/// the world's state).
pub const FORMAT_VERSION: u32 = 5;

/// Bytes before the payload: magic, version, four u64, time, payload length.
const HEADER_LEN: usize = 8 + 4 + 4 * 8 + 8 + 8;

/// What `--resume` tells the user to do with a checkpoint it cannot use: only one
/// checkpoint is kept (a new one replaces the old by an atomic rename), so the run
/// starts again from its first frame.
pub const RERUN: &str = "rerun from frame 1: run again without --resume (or with --force)";

/// A checkpoint: where the run was, and the model's state as bytes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Checkpoint {
    /// Hash of the scene (and settings) it was written for.
    pub scene_hash: u64,
    /// The last frame written before the checkpoint.
    pub frame: u64,
    /// Steps taken.
    pub steps: u64,
    /// Bonds broken so far (directed).
    pub broken_bonds: u64,
    /// Simulation time (s).
    pub time: f64,
    /// The model's state, written with an [`Encoder`].
    pub payload: Vec<u8>,
}

impl Checkpoint {
    /// The file's bytes.
    pub fn encode(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(HEADER_LEN + self.payload.len() + 4);
        out.extend_from_slice(&self.header(self.payload.len() as u64));
        out.extend_from_slice(&self.payload);
        let crc = crc32fast::hash(&out);
        out.extend_from_slice(&crc.to_le_bytes());
        out
    }

    /// The bytes before a payload of `payload_len` bytes.
    fn header(&self, payload_len: u64) -> Vec<u8> {
        let mut out = Vec::with_capacity(HEADER_LEN);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        for v in [self.scene_hash, self.frame, self.steps, self.broken_bonds] {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out.extend_from_slice(&self.time.to_le_bytes());
        out.extend_from_slice(&payload_len.to_le_bytes());
        out
    }

    /// Decodes the bytes of the checkpoint file `path` (named in errors): refuses a
    /// wrong magic or version, a truncated file, trailing bytes and a bad checksum.
    pub fn decode(bytes: &[u8], path: &Path) -> Result<Checkpoint> {
        let mut checkpoint = Self::check(bytes, path)?;
        checkpoint.payload = bytes[HEADER_LEN..bytes.len() - 4].to_vec();
        Ok(checkpoint)
    }

    /// The counters of the checkpoint whose file's bytes are `bytes`, checked as
    /// [`Checkpoint::decode`] does, with an empty payload.
    fn check(bytes: &[u8], path: &Path) -> Result<Checkpoint> {
        let fail = |message: String| CacheError::checkpoint(path, message);
        if bytes.get(..MAGIC.len()) != Some(MAGIC.as_slice()) {
            let what = if bytes.starts_with(b"PFCKPT") {
                "a checkpoint of another perifrac version"
            } else {
                "not a perifrac checkpoint"
            };
            return Err(fail(format!("{what}; {RERUN}")));
        }
        if bytes.len() < HEADER_LEN + 4 {
            return Err(fail(format!(
                "truncated: {} bytes, shorter than the {}-byte header; the checkpoint is \
                 damaged; {RERUN}",
                bytes.len(),
                HEADER_LEN + 4
            )));
        }
        let mut header = Decoder::new(&bytes[MAGIC.len()..HEADER_LEN], path);
        let version = header.take_u32("format version")?;
        if version != FORMAT_VERSION {
            return Err(fail(format!(
                "checkpoint format version {version}, this perifrac reads version \
                 {FORMAT_VERSION}; {RERUN}"
            )));
        }
        let scene_hash = header.take_u64("scene hash")?;
        let frame = header.take_u64("frame")?;
        let steps = header.take_u64("steps")?;
        let broken_bonds = header.take_u64("broken bonds")?;
        let time = header.take_f64("time")?;
        let payload_len = header.take_u64("payload length")?;
        header.finish()?;
        let expected = (HEADER_LEN as u64)
            .checked_add(payload_len)
            .and_then(|n| n.checked_add(4));
        match expected {
            Some(n) if n == bytes.len() as u64 => {}
            Some(n) if n > bytes.len() as u64 => {
                return Err(fail(format!(
                    "truncated: {} bytes, the header announces {n}; the checkpoint is damaged \
                     (last frame it claims: {frame}); {RERUN}",
                    bytes.len()
                )));
            }
            _ => {
                return Err(fail(format!(
                    "{} bytes, the header announces {}; trailing bytes or a damaged header; \
                     {RERUN}",
                    bytes.len(),
                    expected.map_or("more than 2^64".to_string(), |n| n.to_string())
                )));
            }
        }
        let (body, stored) = bytes.split_at(bytes.len() - 4);
        let stored = u32::from_le_bytes([stored[0], stored[1], stored[2], stored[3]]);
        let computed = crc32fast::hash(body);
        if stored != computed {
            return Err(fail(format!(
                "checksum mismatch (stored {stored:#010x}, computed {computed:#010x}): the \
                 checkpoint is damaged (last frame it claims: {frame}); {RERUN}"
            )));
        }
        Ok(Checkpoint {
            scene_hash,
            frame,
            steps,
            broken_bonds,
            time,
            payload: Vec::new(),
        })
    }

    /// Writes the checkpoint atomically.
    pub fn write(&self, path: &Path) -> Result<()> {
        crate::write_atomic(path, &self.encode())
    }

    /// Writes the checkpoint atomically with the payload `save` encodes (in place of
    /// `self.payload`, which is not written), passed to the file in chunks of
    /// [`SPILL_CHUNK`] bytes as it is encoded: the same bytes as [`Checkpoint::write`]
    /// of that payload, without the state held in memory a second and a third time
    /// (the payload, then the file's bytes; for an MPM run, 224 bytes a particle
    /// each). Returns the payload's length.
    pub fn write_encoded(&self, path: &Path, save: impl FnOnce(&mut Encoder)) -> Result<u64> {
        let written = std::cell::Cell::new(HEADER_LEN as u64 + 4);
        let write = |file: &mut std::fs::File| -> std::io::Result<u64> {
            // The header's payload length is known at the end: room for it now.
            file.write_all(&[0; HEADER_LEN])?;
            let mut encoder = Encoder {
                bytes: Vec::with_capacity(SPILL_CHUNK),
                spill: Some(Spill {
                    file: file.try_clone()?,
                    crc: crc32fast::Hasher::new(),
                    len: 0,
                    error: None,
                }),
            };
            save(&mut encoder);
            encoder.spill_bytes();
            let Some(Spill {
                crc, len, error, ..
            }) = encoder.spill
            else {
                return Err(std::io::Error::other(
                    "the checkpoint's encoder has no file",
                ));
            };
            written.set(written.get() + len);
            if let Some(error) = error {
                return Err(error);
            }
            let head = self.header(len);
            let mut whole = crc32fast::Hasher::new();
            whole.update(&head);
            whole.combine(&crc);
            file.write_all(&whole.finalize().to_le_bytes())?;
            file.seek(SeekFrom::Start(0))?;
            file.write_all(&head)?;
            Ok(len)
        };
        crate::layout::write_atomic_file(path, write, || written.get())
    }

    /// Reads and checks the checkpoint at `path`.
    pub fn read(path: &Path) -> Result<Checkpoint> {
        let mut bytes = std::fs::read(path).map_err(|e| CacheError::io(path, e))?;
        let mut checkpoint = Self::check(&bytes, path)?;
        // The payload in the file's own buffer, not copied: the state is large.
        bytes.truncate(bytes.len() - 4);
        bytes.drain(..HEADER_LEN);
        checkpoint.payload = bytes;
        Ok(checkpoint)
    }
}

/// Bytes an [`Encoder`] writing a checkpoint file holds before it passes them on.
pub const SPILL_CHUNK: usize = 1 << 22;

/// Writes a model's state into a checkpoint payload (little-endian; slices with
/// their length first): into memory ([`Encoder::new`], [`Encoder::finish`]), or into
/// a checkpoint file as it goes ([`Checkpoint::write_encoded`]).
#[derive(Debug, Default)]
pub struct Encoder {
    bytes: Vec<u8>,
    spill: Option<Spill>,
}

/// Where an [`Encoder`] of [`Checkpoint::write_encoded`] passes its bytes: the
/// checkpoint's temporary file (a handle of its own at the same offset), the
/// payload's CRC and length so far, the first
/// failed write (encoding goes on; the write reports it at the end).
#[derive(Debug)]
struct Spill {
    file: std::fs::File,
    crc: crc32fast::Hasher,
    len: u64,
    error: Option<std::io::Error>,
}

impl Encoder {
    /// An empty payload.
    pub fn new() -> Encoder {
        Encoder::default()
    }

    /// Appends bytes; an encoder with a spill passes them on every [`SPILL_CHUNK`].
    fn push(&mut self, b: &[u8]) {
        self.bytes.extend_from_slice(b);
        if self.bytes.len() >= SPILL_CHUNK {
            self.spill_bytes();
        }
    }

    /// Passes the bytes held to the spill, if there is one.
    fn spill_bytes(&mut self) {
        let Some(spill) = &mut self.spill else {
            return;
        };
        if spill.error.is_none() {
            if let Err(error) = spill.file.write_all(&self.bytes) {
                spill.error = Some(error);
            }
            spill.crc.update(&self.bytes);
        }
        // Counted after a failed write too: the whole payload is what the file needs.
        spill.len += self.bytes.len() as u64;
        self.bytes.clear();
    }

    /// Appends a u32.
    pub fn put_u32(&mut self, v: u32) {
        self.push(&v.to_le_bytes());
    }

    /// Appends a u64.
    pub fn put_u64(&mut self, v: u64) {
        self.push(&v.to_le_bytes());
    }

    /// Appends an f32.
    pub fn put_f32(&mut self, v: f32) {
        self.push(&v.to_le_bytes());
    }

    /// Appends an f64.
    pub fn put_f64(&mut self, v: f64) {
        self.push(&v.to_le_bytes());
    }

    /// Appends a slice length.
    fn put_len(&mut self, len: usize) {
        self.put_u64(len as u64);
    }

    /// Appends a slice of u32 (its length, then the values).
    pub fn put_u32_slice(&mut self, v: &[u32]) {
        self.put_len(v.len());
        v.iter().for_each(|&x| self.put_u32(x));
    }

    /// Appends a slice of f32 (its length, then the values).
    pub fn put_f32_slice(&mut self, v: &[f32]) {
        self.put_len(v.len());
        v.iter().for_each(|&x| self.put_f32(x));
    }

    /// Appends a slice of f64 (its length, then the values).
    pub fn put_f64_slice(&mut self, v: &[f64]) {
        self.put_len(v.len());
        v.iter().for_each(|&x| self.put_f64(x));
    }

    /// Appends a slice of 3-vectors of f64 (its length in vectors, then x y z of each).
    pub fn put_f64x3_slice(&mut self, v: &[[f64; 3]]) {
        self.put_len(v.len());
        v.iter().flatten().for_each(|&x| self.put_f64(x));
    }

    /// The payload of an encoder made by [`Encoder::new`].
    pub fn finish(self) -> Vec<u8> {
        self.bytes
    }
}

/// Reads a model's state back from a checkpoint payload; every failure names the
/// file and the field that was short or invalid.
#[derive(Debug)]
pub struct Decoder<'a> {
    bytes: &'a [u8],
    at: usize,
    path: &'a Path,
}

impl<'a> Decoder<'a> {
    /// Reads `bytes`, the payload of the checkpoint file `path` (named in errors).
    pub fn new(bytes: &'a [u8], path: &'a Path) -> Decoder<'a> {
        Decoder { bytes, at: 0, path }
    }

    /// A failure reading `field`.
    pub fn error(&self, field: &str, message: impl std::fmt::Display) -> CacheError {
        CacheError::checkpoint(
            self.path,
            format!("checkpoint field '{field}': {message}; {RERUN}"),
        )
    }

    /// Bytes not read yet.
    pub fn remaining(&self) -> usize {
        self.bytes.len() - self.at
    }

    fn take<const N: usize>(&mut self, field: &str) -> Result<[u8; N]> {
        let Some(s) = self.bytes.get(self.at..self.at + N) else {
            return Err(self.error(
                field,
                format!(
                    "needs {N} bytes, {} left: the checkpoint is truncated",
                    self.remaining()
                ),
            ));
        };
        self.at += N;
        let mut a = [0u8; N];
        a.copy_from_slice(s);
        Ok(a)
    }

    /// Reads a u32.
    pub fn take_u32(&mut self, field: &str) -> Result<u32> {
        Ok(u32::from_le_bytes(self.take(field)?))
    }

    /// Reads a u64.
    pub fn take_u64(&mut self, field: &str) -> Result<u64> {
        Ok(u64::from_le_bytes(self.take(field)?))
    }

    /// Reads an f32.
    pub fn take_f32(&mut self, field: &str) -> Result<f32> {
        Ok(f32::from_le_bytes(self.take(field)?))
    }

    /// Reads an f64.
    pub fn take_f64(&mut self, field: &str) -> Result<f64> {
        Ok(f64::from_le_bytes(self.take(field)?))
    }

    /// Reads a slice length, which must be `len` (what the scene gives), and checks
    /// that `len` values of `size` bytes remain.
    fn take_len(&mut self, field: &str, len: usize, size: usize) -> Result<()> {
        let stored = self.take_u64(field)?;
        if stored != len as u64 {
            return Err(self.error(
                field,
                format!("{stored} values in the checkpoint, the scene gives {len}"),
            ));
        }
        let needed = len.saturating_mul(size);
        if needed > self.remaining() {
            return Err(self.error(
                field,
                format!(
                    "{len} values need {needed} bytes, {} left: the checkpoint is truncated",
                    self.remaining()
                ),
            ));
        }
        Ok(())
    }

    /// Reads a slice of `len` u32 written by [`Encoder::put_u32_slice`].
    pub fn take_u32_slice(&mut self, field: &str, len: usize) -> Result<Vec<u32>> {
        self.take_len(field, len, 4)?;
        (0..len).map(|_| self.take_u32(field)).collect()
    }

    /// Reads a slice of `len` u32 and refuses any value for which `valid` is false
    /// (naming the first such value and its index).
    pub fn take_u32_slice_checked(
        &mut self,
        field: &str,
        len: usize,
        valid: impl Fn(u32) -> bool,
    ) -> Result<Vec<u32>> {
        let values = self.take_u32_slice(field, len)?;
        if let Some(i) = values.iter().position(|&v| !valid(v)) {
            return Err(self.error(field, format!("value {} at {i} is out of range", values[i])));
        }
        Ok(values)
    }

    /// Reads a slice of `len` indices, each below `limit` (e.g. the particle count).
    pub fn take_u32_slice_bounded(
        &mut self,
        field: &str,
        len: usize,
        limit: u32,
    ) -> Result<Vec<u32>> {
        self.take_u32_slice_checked(field, len, |v| v < limit)
    }

    /// Reads a slice of `len` f32 written by [`Encoder::put_f32_slice`].
    pub fn take_f32_slice(&mut self, field: &str, len: usize) -> Result<Vec<f32>> {
        self.take_len(field, len, 4)?;
        (0..len).map(|_| self.take_f32(field)).collect()
    }

    /// Reads a slice of `len` f64 written by [`Encoder::put_f64_slice`].
    pub fn take_f64_slice(&mut self, field: &str, len: usize) -> Result<Vec<f64>> {
        self.take_len(field, len, 8)?;
        (0..len).map(|_| self.take_f64(field)).collect()
    }

    /// Reads a slice of `len` 3-vectors written by [`Encoder::put_f64x3_slice`].
    pub fn take_f64x3_slice(&mut self, field: &str, len: usize) -> Result<Vec<[f64; 3]>> {
        self.take_len(field, len, 24)?;
        (0..len)
            .map(|_| {
                Ok([
                    self.take_f64(field)?,
                    self.take_f64(field)?,
                    self.take_f64(field)?,
                ])
            })
            .collect()
    }

    /// Reads an f64 and refuses a NaN or an infinity.
    pub fn take_finite_f64(&mut self, field: &str) -> Result<f64> {
        let v = self.take_f64(field)?;
        if !v.is_finite() {
            return Err(self.error(field, format!("{v} is not a finite number")));
        }
        Ok(v)
    }

    /// Reads a slice of `len` f64 and refuses a NaN or an infinity (naming the
    /// first and its index).
    pub fn take_finite_f64_slice(&mut self, field: &str, len: usize) -> Result<Vec<f64>> {
        let values = self.take_f64_slice(field, len)?;
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(self.error(
                field,
                format!("value {} at {i} is not a finite number", values[i]),
            ));
        }
        Ok(values)
    }

    /// Reads a slice of `len` 3-vectors and refuses a NaN or an infinity in any
    /// component (naming the first vector and its index).
    pub fn take_finite_f64x3_slice(&mut self, field: &str, len: usize) -> Result<Vec<[f64; 3]>> {
        let values = self.take_f64x3_slice(field, len)?;
        if let Some(i) = values.iter().position(|v| !v.iter().all(|c| c.is_finite())) {
            return Err(self.error(
                field,
                format!("{:?} at {i} is not a finite vector", values[i]),
            ));
        }
        Ok(values)
    }

    /// Ends decoding; refuses bytes left over (a payload of another layout).
    pub fn finish(self) -> Result<()> {
        match self.remaining() {
            0 => Ok(()),
            n => Err(CacheError::checkpoint(
                self.path,
                format!(
                    "{n} bytes left after the last field: the checkpoint was written by \
                     another model or version; {RERUN}"
                ),
            )),
        }
    }
}

#[cfg(test)]
mod tests;
