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
use rayon::prelude::*;

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

/// Frames drawn in batches of this many (in parallel), each indexed and dropped before the next
/// batch is drawn: the animation holds one byte per pixel and frame, not three.
const BATCH: usize = 8;

/// A drawn frame (packed RGB) or why it could not be drawn.
pub(crate) type Drawn = Result<Vec<u8>, String>;

/// `count` frames of `size` pixels, frame `k` drawn on demand by `draw(k)` as packed RGB (3 bytes
/// per pixel, row-major).
pub(crate) struct RgbFrames<F> {
    size: (u16, u16),
    count: usize,
    draw: F,
}

impl<F: Fn(usize) -> Drawn + Sync> RgbFrames<F> {
    /// `count` frames of `size` drawn by `draw`; each must hold `3 · width · height` bytes.
    pub(crate) fn new(size: (u32, u32), count: usize, draw: F) -> Result<Self, String> {
        let (Ok(w), Ok(h)) = (u16::try_from(size.0), u16::try_from(size.1)) else {
            return Err(format!("a GIF is at most 65535 pixels a side, {} × {} asked", size.0, size.1));
        };
        if count == 0 {
            return Err("an animation needs at least one frame".into());
        }
        Ok(Self { size: (w, h), count, draw })
    }

    /// Frame `k`, checked for its size.
    fn frame(&self, k: usize) -> Drawn {
        let frame = (self.draw)(k)?;
        let bytes = 3 * usize::from(self.size.0) * usize::from(self.size.1);
        if frame.len() != bytes {
            let (w, h) = self.size;
            return Err(format!("frame {k} holds {} bytes, not the {bytes} of {w} × {h} RGB", frame.len()));
        }
        Ok(frame)
    }

    /// The frames that teach the palette: up to [`TRAINING_FRAMES`], evenly spread, drawn in
    /// parallel, as `(index, frame)`.
    fn training(&self) -> Result<Vec<(usize, Vec<u8>)>, String> {
        let stride = self.count.div_ceil(TRAINING_FRAMES);
        let picked: Vec<usize> = (0..self.count).step_by(stride).collect();
        picked.into_par_iter().map(|k| self.frame(k).map(|f| (k, f))).collect()
    }

    /// The shared palette (256 RGB entries) learnt from the training frames.
    fn quantiser(training: &[(usize, Vec<u8>)]) -> NeuQuant {
        let rgba: Vec<u8> =
            training.iter().flat_map(|(_, f)| f.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255])).collect();
        NeuQuant::new(SAMPLING, 256, &rgba)
    }

    /// Writes a looping GIF to `path`, each frame shown `delay_ms` (rounded to 10 ms). After the
    /// first, each frame is stored as the rectangle where it differs from the one before, drawn
    /// over it (disposal "keep"): the same pictures for a fraction of the bytes and of the
    /// compression work. The frames are drawn and compressed in parallel.
    pub(crate) fn write(&self, path: &Path, delay_ms: u32) -> Result<(), String> {
        let mut training = self.training()?;
        let nq = Self::quantiser(&training);
        let palette = nq.color_map_rgb();
        let indexed = self.indexed(&nq, &mut training)?;
        let (w, h) = self.size;
        let delay = u16::try_from(delay_ms.div_ceil(10)).unwrap_or(u16::MAX);
        let frames: Vec<gif::Frame<'static>> = (0..indexed.len())
            .into_par_iter()
            .map(|k| {
                let rect = if k == 0 { Rect::whole(w, h) } else { Rect::changed(&indexed[k - 1], &indexed[k], w, h) };
                let mut frame = gif::Frame {
                    width: rect.width,
                    height: rect.height,
                    left: rect.left,
                    top: rect.top,
                    delay,
                    dispose: gif::DisposalMethod::Keep,
                    buffer: Cow::Owned(rect.cut(&indexed[k], w)),
                    ..gif::Frame::default()
                };
                frame.make_lzw_pre_encoded();
                frame
            })
            .collect();
        let file = File::create(path).map_err(|e| e.to_string())?;
        let mut encoder = gif::Encoder::new(BufWriter::new(file), w, h, &palette).map_err(|e| e.to_string())?;
        encoder.set_repeat(gif::Repeat::Infinite).map_err(|e| e.to_string())?;
        for frame in &frames {
            encoder.write_lzw_pre_encoded_frame(frame).map_err(|e| e.to_string())?;
        }
        encoder.into_inner().map_err(|e| e.to_string())?.into_inner().map_err(|e| e.to_string())?;
        Ok(())
    }

    /// Every frame as palette indices, each colour looked up once: drawn [`BATCH`] at a time (the
    /// training frames taken, not drawn again), indexed in order, and dropped.
    fn indexed(&self, nq: &NeuQuant, training: &mut [(usize, Vec<u8>)]) -> Result<Vec<Vec<u8>>, String> {
        let mut index: HashMap<u32, u8, BuildHasherDefault<ColourHasher>> = HashMap::default();
        let mut indexed = Vec::with_capacity(self.count);
        let all: Vec<usize> = (0..self.count).collect();
        for batch in all.chunks(BATCH) {
            let taught = |k: usize| training.iter().any(|(t, _)| *t == k);
            let drawn: Vec<Option<Vec<u8>>> = batch
                .par_iter()
                .map(|&k| if taught(k) { Ok(None) } else { self.frame(k).map(Some) })
                .collect::<Result<_, String>>()?;
            for (&k, rgb) in batch.iter().zip(drawn) {
                let rgb = match rgb {
                    Some(rgb) => rgb,
                    None => training
                        .iter_mut()
                        .find(|(t, _)| *t == k)
                        .map(|(_, f)| std::mem::take(f))
                        .ok_or_else(|| format!("frame {k} taught the palette but was not kept"))?,
                };
                indexed.push(index_frame(&rgb, nq, &mut index));
            }
        }
        Ok(indexed)
    }
}

/// A frame's palette indices; `index` remembers each colour's entry across frames.
fn index_frame(rgb: &[u8], nq: &NeuQuant, index: &mut HashMap<u32, u8, BuildHasherDefault<ColourHasher>>) -> Vec<u8> {
    // Most pixels repeat their left neighbour (background, fills): those skip the map.
    let mut last: Option<(u32, u8)> = None;
    rgb.chunks_exact(3)
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
        .collect()
}

/// A rectangle of a frame, pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Rect {
    left: u16,
    top: u16,
    width: u16,
    height: u16,
}

impl Rect {
    fn whole(width: u16, height: u16) -> Self {
        Rect { left: 0, top: 0, width, height }
    }

    /// The bounding box of the pixels where `next` differs from `prev` (frames `w` wide); one
    /// pixel when none does (a GIF frame cannot be empty).
    fn changed(prev: &[u8], next: &[u8], w: u16, h: u16) -> Self {
        let w = usize::from(w);
        let rows: Vec<usize> =
            (0..usize::from(h)).filter(|&y| prev[y * w..(y + 1) * w] != next[y * w..(y + 1) * w]).collect();
        let (Some(&top), Some(&bottom)) = (rows.first(), rows.last()) else {
            return Rect { left: 0, top: 0, width: 1, height: 1 };
        };
        let (mut left, mut right) = (w, 0);
        for y in top..=bottom {
            let (a, b) = (&prev[y * w..(y + 1) * w], &next[y * w..(y + 1) * w]);
            if let Some(x) = (0..w).find(|&x| a[x] != b[x]) {
                left = left.min(x);
                right = right.max((x..w).rev().find(|&x| a[x] != b[x]).unwrap_or(x));
            }
        }
        // Both lie within a frame of at most 65535 pixels a side.
        let px = |v: usize| u16::try_from(v).unwrap_or(u16::MAX);
        Rect { left: px(left), top: px(top), width: px(right - left + 1), height: px(bottom - top + 1) }
    }

    /// The rectangle's pixels out of a frame `w` wide.
    fn cut(self, frame: &[u8], w: u16) -> Vec<u8> {
        let (w, left, width) = (usize::from(w), usize::from(self.left), usize::from(self.width));
        (usize::from(self.top)..usize::from(self.top) + usize::from(self.height))
            .flat_map(|y| frame[y * w + left..y * w + left + width].iter().copied())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The frames `frames`, drawn by copying.
    fn drawn(size: (u32, u32), frames: &[Vec<u8>]) -> Result<RgbFrames<impl Fn(usize) -> Drawn + Sync + '_>, String> {
        RgbFrames::new(size, frames.len(), |k| Ok(frames[k].clone()))
    }

    /// The pictures a viewer shows: each frame drawn over the last at its offset (every frame
    /// of ours keeps the one before).
    fn decode(path: &Path) -> (Vec<u8>, Vec<Vec<u8>>) {
        let mut options = gif::DecodeOptions::new();
        options.set_color_output(gif::ColorOutput::RGBA);
        let mut decoder = options.read_info(File::open(path).unwrap()).unwrap();
        let (w, h) = (usize::from(decoder.width()), usize::from(decoder.height()));
        let mut canvas = vec![0u8; 4 * w * h];
        let mut frames = Vec::new();
        while let Some(f) = decoder.read_next_frame().unwrap() {
            assert_eq!(f.dispose, gif::DisposalMethod::Keep);
            let (left, top, fw) = (usize::from(f.left), usize::from(f.top), usize::from(f.width));
            for (row, line) in f.buffer.chunks_exact(4 * fw).enumerate() {
                let at = 4 * ((top + row) * w + left);
                canvas[at..at + 4 * fw].copy_from_slice(line);
            }
            frames.push(canvas.clone());
        }
        (decoder.global_palette().unwrap().to_vec(), frames)
    }

    /// The largest difference of a colour channel between RGB frames and their RGBA decoding.
    fn worst_level_error(frames: &[Vec<u8>], decoded: &[Vec<u8>]) -> u8 {
        frames
            .iter()
            .zip(decoded)
            .flat_map(|(rgb, rgba)| {
                let back = rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]);
                rgb.iter().zip(back).map(|(a, b)| a.abs_diff(b))
            })
            .max()
            .unwrap_or(0)
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
        drawn((w as u32, h as u32), &frames).unwrap().write(&path, 80).unwrap();
        let (palette, decoded) = decode(&path);
        std::fs::remove_file(&path).unwrap();
        assert_eq!(palette.len(), 3 * 256);
        assert_eq!(decoded.len(), 3);
        let worst = worst_level_error(&frames, &decoded);
        assert!(worst <= 2, "a flat colour came back {worst} levels off");
    }

    #[test]
    fn only_the_changed_rectangle_is_stored_and_the_pictures_come_back_whole() {
        // A 3 × 2 blue block moves right by 2 pixels per frame over white, beside a blue right
        // half (so the palette learns both colours); the third frame repeats the second.
        let (w, h) = (16usize, 10usize);
        let picture = |x0: usize| -> Vec<u8> {
            (0..w * h)
                .flat_map(|i| {
                    let (x, y) = (i % w, i / w);
                    if x >= 8 || ((x0..x0 + 3).contains(&x) && (4..6).contains(&y)) {
                        [33, 102, 172]
                    } else {
                        [255, 255, 255]
                    }
                })
                .collect()
        };
        let frames = vec![picture(1), picture(3), picture(3)];
        let path = std::env::temp_dir().join(format!("catflip-gif-rect-test-{}.gif", std::process::id()));
        drawn((w as u32, h as u32), &frames).unwrap().write(&path, 80).unwrap();
        let mut decoder = gif::DecodeOptions::new().read_info(File::open(&path).unwrap()).unwrap();
        let mut rects = Vec::new();
        while let Some(f) = decoder.read_next_frame().unwrap() {
            rects.push((f.left, f.top, f.width, f.height));
        }
        // Columns 1..=5 of rows 4..=5 change between the first two; nothing after.
        assert_eq!(rects, vec![(0, 0, 16, 10), (1, 4, 5, 2), (0, 0, 1, 1)]);
        let (_, decoded) = decode(&path);
        std::fs::remove_file(&path).unwrap();
        let worst = worst_level_error(&frames, &decoded);
        assert!(worst <= 2, "a picture came back {worst} levels off");
    }

    #[test]
    fn a_frame_of_the_wrong_size_is_refused() {
        let frames = vec![vec![0; 48], vec![0; 47]];
        let path = std::env::temp_dir().join(format!("catflip-gif-size-test-{}.gif", std::process::id()));
        let err = drawn((4, 4), &frames).unwrap().write(&path, 80).err().unwrap();
        let _ = std::fs::remove_file(&path);
        assert_eq!(err, "frame 1 holds 47 bytes, not the 48 of 4 × 4 RGB");
    }
}
