//! Animated GIF with one palette shared by every frame.
//!
//! plotters' GIF backend quantises each frame on its own (NeuQuant per frame), which made the
//! animation the slowest part of `catflip run`. Our frames share one scene and one set of
//! colours, so one palette serves all of them: it is learnt once, by NeuQuant, from a sample of
//! the frames, and each frame is then mapped colour by colour (a frame has a few thousand
//! distinct colours, mostly anti-aliased edges, against 360 000 pixels). The output is
//! deterministic: the same frames give the same bytes.

use std::borrow::Cow;
use std::collections::HashMap;
use std::fs::File;
use std::hash::{BuildHasherDefault, Hasher};
use std::io::BufWriter;
use std::path::Path;

use color_quant::NeuQuant;

/// NeuQuant's sampling factor (1 = every pixel, 30 = fastest); 10 is the GIF convention.
const SAMPLING: i32 = 10;
/// At most this many frames, evenly spread, teach the palette.
const TRAINING_FRAMES: usize = 4;

/// A multiplicative hash of a packed colour (the map's keys are a few thousand colours, not
/// adversarial input, so SipHash's protection buys nothing here).
#[derive(Default)]
struct ColourHasher(u64);

impl Hasher for ColourHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0.rotate_left(5) ^ u64::from(b)).wrapping_mul(0x517c_c1b7_2722_0a95);
        }
    }
    fn write_u32(&mut self, x: u32) {
        // The map indexes by the low bits: fold the product's well-mixed high half into them.
        let h = u64::from(x).wrapping_mul(0x9e37_79b9_7f4a_7c15);
        self.0 = h ^ (h >> 32);
    }
}

/// Frames of `size` pixels as packed RGB (3 bytes per pixel, row-major).
pub(crate) struct RgbFrames {
    size: (u16, u16),
    frames: Vec<Vec<u8>>,
}

impl RgbFrames {
    /// Frames of `size`; each must hold `3 · width · height` bytes.
    pub(crate) fn new(size: (u32, u32), frames: Vec<Vec<u8>>) -> Result<Self, String> {
        let (Ok(w), Ok(h)) = (u16::try_from(size.0), u16::try_from(size.1)) else {
            return Err(format!("a GIF is at most 65535 pixels a side, {} × {} asked", size.0, size.1));
        };
        let bytes = 3 * usize::from(w) * usize::from(h);
        if frames.is_empty() {
            return Err("an animation needs at least one frame".into());
        }
        if let Some(k) = frames.iter().position(|f| f.len() != bytes) {
            return Err(format!("frame {k} holds {} bytes, not the {bytes} of {w} × {h} RGB", frames[k].len()));
        }
        Ok(Self { size: (w, h), frames })
    }

    /// The shared palette (256 RGB entries) learnt from up to [`TRAINING_FRAMES`] frames.
    fn quantiser(&self) -> NeuQuant {
        let stride = self.frames.len().div_ceil(TRAINING_FRAMES);
        let rgba: Vec<u8> = self
            .frames
            .iter()
            .step_by(stride)
            .flat_map(|f| f.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]))
            .collect();
        NeuQuant::new(SAMPLING, 256, &rgba)
    }

    /// Writes a looping GIF to `path`, each frame shown `delay_ms` (rounded to 10 ms).
    pub(crate) fn write(&self, path: &Path, delay_ms: u32) -> Result<(), String> {
        let nq = self.quantiser();
        let palette = nq.color_map_rgb();
        let mut index: HashMap<u32, u8, BuildHasherDefault<ColourHasher>> = HashMap::default();
        let file = File::create(path).map_err(|e| e.to_string())?;
        let (w, h) = self.size;
        let mut encoder = gif::Encoder::new(BufWriter::new(file), w, h, &palette).map_err(|e| e.to_string())?;
        encoder.set_repeat(gif::Repeat::Infinite).map_err(|e| e.to_string())?;
        let delay = u16::try_from(delay_ms.div_ceil(10)).unwrap_or(u16::MAX);
        for rgb in &self.frames {
            // Most pixels repeat their left neighbour (background, fills): those skip the map.
            let mut last: Option<(u32, u8)> = None;
            let pixels: Vec<u8> = rgb
                .chunks_exact(3)
                .map(|p| {
                    let key = u32::from_le_bytes([p[0], p[1], p[2], 0]);
                    if let Some((_, i)) = last.filter(|&(k, _)| k == key) {
                        return i;
                    }
                    // NeuQuant's palette has 256 entries, so an index always fits a byte.
                    let i = *index.entry(key).or_insert_with(|| nq.index_of(&[p[0], p[1], p[2], 255]) as u8);
                    last = Some((key, i));
                    i
                })
                .collect();
            let frame = gif::Frame { width: w, height: h, delay, buffer: Cow::Owned(pixels), ..gif::Frame::default() };
            encoder.write_frame(&frame).map_err(|e| e.to_string())?;
        }
        encoder.into_inner().map_err(|e| e.to_string())?.into_inner().map_err(|e| e.to_string())?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decode(path: &Path) -> (Vec<u8>, Vec<Vec<u8>>) {
        let mut options = gif::DecodeOptions::new();
        options.set_color_output(gif::ColorOutput::RGBA);
        let mut decoder = options.read_info(File::open(path).unwrap()).unwrap();
        let mut frames = Vec::new();
        while let Some(f) = decoder.read_next_frame().unwrap() {
            frames.push(f.buffer.to_vec());
        }
        (decoder.global_palette().unwrap().to_vec(), frames)
    }

    #[test]
    fn a_few_flat_colours_come_back_within_two_levels() {
        // Four colours of the scene in four quadrants, moved by one column per frame: a shared
        // palette of 256 entries must reproduce each exactly.
        let colours = [[255, 255, 255], [253, 208, 162], [33, 102, 172], [215, 25, 60]];
        let (w, h) = (40usize, 20usize);
        let frames: Vec<Vec<u8>> = (0..3)
            .map(|shift| {
                (0..w * h)
                    .flat_map(|i| {
                        let (x, y) = ((i % w + shift) % w, i / w);
                        colours[usize::from(x >= w / 2) + 2 * usize::from(y >= h / 2)]
                    })
                    .collect()
            })
            .collect();
        let path = std::env::temp_dir().join(format!("catflip-gif-test-{}.gif", std::process::id()));
        RgbFrames::new((w as u32, h as u32), frames.clone()).unwrap().write(&path, 80).unwrap();
        let (palette, decoded) = decode(&path);
        std::fs::remove_file(&path).unwrap();
        assert_eq!(palette.len(), 3 * 256);
        assert_eq!(decoded.len(), 3);
        for (rgb, rgba) in frames.iter().zip(&decoded) {
            let back: Vec<u8> = rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
            let worst = rgb.iter().zip(&back).map(|(a, b)| a.abs_diff(*b)).max().unwrap();
            assert!(worst <= 2, "a flat colour came back {worst} levels off");
        }
    }

    #[test]
    fn a_frame_of_the_wrong_size_is_refused() {
        let err = RgbFrames::new((4, 4), vec![vec![0; 48], vec![0; 47]]).err().unwrap();
        assert_eq!(err, "frame 1 holds 47 bytes, not the 48 of 4 × 4 RGB");
    }
}
