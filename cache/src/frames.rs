//! Frame ranges: the part of a cache a stage works on (`perifrac surface --frames
//! 10..20`, `perifrac render --frames 10..20`), so that a farm's array job can split
//! a shot's per-frame work across machines, each writing only its frames' files into
//! the one cache.

use std::ops::Range;

/// Frames `first` to `last` of a cache, both included (as a farm's frame ranges are:
/// Deadline's `10-20`, a Slurm array's `--array=1-8`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameRange {
    /// The first frame (from 1).
    pub first: usize,
    /// The last frame, at least `first`.
    pub last: usize,
}

impl FrameRange {
    /// Every frame of a cache of `frames` frames.
    pub fn all(frames: usize) -> FrameRange {
        FrameRange {
            first: 1,
            last: frames,
        }
    }

    /// Parses `A..B` or `A-B` (both ends included) or a single frame `A`; `flag`
    /// names the option in the error.
    pub fn parse(flag: &str, text: &str) -> std::result::Result<FrameRange, String> {
        let bad = |why: &str| {
            format!(
                "{flag} takes a frame range FIRST..LAST (both included, frames from 1), e.g. \
                 10..20, or one frame; got '{text}': {why}"
            )
        };
        let number = |s: &str| -> std::result::Result<usize, String> {
            let n: usize = s.trim().parse().map_err(|_| bad("not a frame number"))?;
            if n == 0 {
                return Err(bad("frames are numbered from 1"));
            }
            Ok(n)
        };
        let (first, last) = match text.split_once("..").or_else(|| text.split_once('-')) {
            Some((a, b)) => (number(a)?, number(b)?),
            None => {
                let n = number(text)?;
                (n, n)
            }
        };
        if last < first {
            return Err(bad("the last frame is before the first"));
        }
        Ok(FrameRange { first, last })
    }

    /// The range cut to a cache of `frames` frames: a farm's last chunk may run past
    /// the end (OpenCue's `#FRAME_END#` of a range its chunk size does not divide),
    /// and the frames past it are left out (`Some` of a note saying so); a range
    /// starting past the end is an error saying what the cache holds.
    pub fn within(
        &self,
        frames: usize,
    ) -> std::result::Result<(FrameRange, Option<String>), String> {
        if self.first > frames {
            return Err(format!(
                "frames {self} asked for, but the cache has frames 1..{frames}; pass a range \
                 within them"
            ));
        }
        if self.last <= frames {
            return Ok((*self, None));
        }
        let cut = FrameRange {
            first: self.first,
            last: frames,
        };
        let note = format!(
            "frames {self} asked for and the cache ends at frame {frames}: working on {cut}"
        );
        Ok((cut, Some(note)))
    }

    /// Checks the range against a cache of `frames` frames, saying what it holds.
    pub fn check(&self, frames: usize) -> std::result::Result<(), String> {
        if self.last > frames {
            return Err(format!(
                "frames {self} asked for, but the cache has frames 1..{frames}; pass a range \
                 within them"
            ));
        }
        Ok(())
    }

    /// Whether the range is every frame of a cache of `frames` frames.
    pub fn is_all(&self, frames: usize) -> bool {
        self.first == 1 && self.last >= frames
    }

    /// Whether frame `k` is in the range.
    pub fn contains(&self, k: usize) -> bool {
        (self.first..=self.last).contains(&k)
    }

    /// The frames, in order (`first..last + 1`: an exact-size range, so rayon
    /// splits it by index).
    pub fn frames(&self) -> Range<usize> {
        self.first..self.last + 1
    }

    /// How many frames.
    pub fn len(&self) -> usize {
        self.last + 1 - self.first
    }

    /// Never: a range holds at least one frame.
    pub fn is_empty(&self) -> bool {
        false
    }
}

impl std::fmt::Display for FrameRange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}..{}", self.first, self.last)
    }
}

/// The frame a per-frame file of a stage belongs to: `NNNN.ext` and `NNNN_what.ext`
/// (`vdb/0007.vdb`, `surface/0007_debris.ply` → 7); `None` for the others
/// (`surface/animated.glb`, `preview/frame_0007.png`, `preview/turntable_001.png`).
pub fn frame_of_file(name: &str) -> Option<usize> {
    let file = name.rsplit('/').next()?;
    let digits = file.get(..4)?;
    let rest = file.get(4..)?;
    (digits.bytes().all(|b| b.is_ascii_digit()) && (rest.starts_with('.') || rest.starts_with('_')))
        .then(|| digits.parse().ok())
        .flatten()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_parse_both_ends_included() {
        let r = FrameRange::parse("--frames", "10..20").unwrap();
        assert_eq!((r.first, r.last, r.len()), (10, 20, 11));
        assert_eq!(FrameRange::parse("--frames", "3-4").unwrap().len(), 2);
        assert_eq!(FrameRange::parse("--frames", "7").unwrap().frames(), 7..8);
        for bad in ["0..3", "5..2", "a..b", "", "1..", "..4"] {
            let e = FrameRange::parse("--frames", bad).unwrap_err();
            assert!(e.contains("--frames") && e.contains(bad), "{e}");
        }
        assert!(r.check(20).is_ok());
        let (cut, note) = r.within(15).unwrap();
        assert_eq!((cut.first, cut.last), (10, 15));
        assert!(note.unwrap().contains("ends at frame 15"));
        assert_eq!(r.within(20).unwrap(), (r, None));
        assert!(r.within(9).unwrap_err().contains("1..9"));
        assert!(r.check(19).unwrap_err().contains("1..19"));
        assert!(FrameRange::all(5).is_all(5) && !r.is_all(20));
    }

    #[test]
    fn per_frame_files_name_their_frame() {
        assert_eq!(frame_of_file("vdb/0007.vdb"), Some(7));
        assert_eq!(frame_of_file("surface/0012_debris.ply"), Some(12));
        assert_eq!(frame_of_file("surface/animated.glb"), None);
        assert_eq!(frame_of_file("preview/frame_0007.png"), None);
        assert_eq!(frame_of_file("preview/turntable_001.png"), None);
        assert_eq!(frame_of_file("preview/contact_sheet.png"), None);
    }
}
