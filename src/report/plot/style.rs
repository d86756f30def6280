//! What every figure shares: the embedded font, the colours, and the PNG + SVG writer.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use plotters_backend::DrawingErrorKind;

use super::raster::Raster;
use super::PlotError;

/// Size of every static PNG, pixels (width, height).
pub const PNG_SIZE: (u32, u32) = (1000, 600);
/// Size of every static SVG, in SVG user units (width, height).
pub const SVG_SIZE: (u32, u32) = (1000, 600);

/// The font family every text style here uses; the embedded DejaVu Sans is registered under it.
pub(crate) const FAMILY: &str = "sans-serif";

/// Registers the embedded DejaVu Sans with plotters' `ab_glyph` renderer, once per process.
pub(crate) fn ensure_fonts() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            let faces = [
                (FontStyle::Normal, dejavu::sans::regular()),
                (FontStyle::Bold, dejavu::sans::bold()),
                (FontStyle::Oblique, dejavu::sans::oblique()),
                (FontStyle::Italic, dejavu::sans::oblique()),
            ];
            for (style, bytes) in faces {
                register_font(FAMILY, style, bytes).map_err(|_| format!("the {} face was rejected", style.as_str()))?;
            }
            Ok(())
        })
        .clone()
        .map_err(PlotError::Font)
}

/// Regular text of the registered family, `size` pixels, black.
pub(crate) fn text(size: f64) -> TextStyle<'static> {
    FontDesc::new(FontFamily::Name(FAMILY), size, FontStyle::Normal).color(&BLACK)
}

/// Bold text of the registered family, `size` pixels, black.
pub(crate) fn bold(size: f64) -> TextStyle<'static> {
    FontDesc::new(FontFamily::Name(FAMILY), size, FontStyle::Bold).color(&BLACK)
}

/// Tableau 10: distinguishable, and the default of many plotting tools.
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Colour of the `i`-th series (the palette repeats; [`dashed`] tells the repeats apart).
pub(crate) fn colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Whether the `i`-th series is drawn dashed: every other pass through the palette.
pub(crate) fn dashed(i: usize) -> bool {
    (i / PALETTE.len()) % 2 == 1
}

/// Grey for reference lines and phase boundaries.
pub(crate) const GUIDE: RGBColor = RGBColor(110, 110, 110);

/// A figure that can draw itself on any plotters backend.
pub(crate) trait Figure {
    /// Draws the whole figure on `root`; the message says what failed.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>;
}

/// A plotters error as a message.
pub(crate) fn failed<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> String {
    e.to_string()
}

/// A plotters error on saving a figure as a message. The bitmap backend's own errors print as
/// Rust `Debug` text (`ImageError(IoError(Custom { … }))`), so its I/O and encoder errors are
/// said by their own message: what the OS said, e.g. "No space left on device (os error 28)".
pub(crate) fn save_failed<E: std::error::Error + Send + Sync + 'static>(e: DrawingAreaErrorKind<E>) -> String {
    use plotters_bitmap::BitMapBackendError;
    let DrawingAreaErrorKind::BackendError(DrawingErrorKind::DrawingError(inner)) = &e else {
        return failed(e);
    };
    match (inner as &dyn std::any::Any).downcast_ref::<BitMapBackendError>() {
        Some(BitMapBackendError::IOError(io)) => io.to_string(),
        Some(BitMapBackendError::ImageError(image)) => image.to_string(),
        Some(BitMapBackendError::InvalidBuffer) => "the bitmap's pixel buffer has the wrong size".into(),
        _ => failed(e),
    }
}

/// Creates `dir` (and its parents) if needed.
pub(crate) fn create_dir(dir: &Path) -> Result<(), PlotError> {
    std::fs::create_dir_all(dir).map_err(|source| PlotError::CreateDir { path: dir.to_path_buf(), source })
}

/// Writes `figure` as `dir/stem.png` and `dir/stem.svg`; returns both paths.
pub(crate) fn write_png_svg(dir: &Path, stem: &str, figure: &impl Figure) -> Result<Vec<PathBuf>, PlotError> {
    ensure_fonts()?;
    create_dir(dir)?;
    let png = dir.join(format!("{stem}.png"));
    render(&png, Raster::new(BitMapBackend::new(&png, PNG_SIZE)).into_drawing_area(), figure)?;
    png_written(&png).map_err(|message| PlotError::Write { path: png.clone(), message })?;
    let svg = dir.join(format!("{stem}.svg"));
    // Drawn into memory and written here: plotters' SVG file target drops its buffered writer
    // without a flush, so an error on the last write would be lost.
    let mut text = String::new();
    render(&svg, SVGBackend::with_string(&mut text, SVG_SIZE).into_drawing_area(), figure)?;
    std::fs::write(&svg, text).map_err(|e| PlotError::Write { path: svg.clone(), message: e.to_string() })?;
    Ok(vec![png, svg])
}

/// Checks that a PNG plotters saved is complete. plotters saves through the `image` crate, whose
/// buffered writer is dropped without a flush, so an error on the last write (a full disk) is
/// not reported; the PNG end chunk (`IEND`) is the last thing written, so a file that ends with
/// it was written whole.
pub(crate) fn png_written(path: &Path) -> Result<(), String> {
    use std::io::{Read, Seek, SeekFrom};
    const IEND: [u8; 12] = [0, 0, 0, 0, b'I', b'E', b'N', b'D', 0xAE, 0x42, 0x60, 0x82];
    let mut tail = [0u8; 12];
    let mut file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let complete = file.seek(SeekFrom::End(-12)).is_ok() && file.read_exact(&mut tail).is_ok() && tail == IEND;
    if complete {
        Ok(())
    } else {
        Err("the PNG was not written whole (a write failed: is the disk full?)".into())
    }
}

/// Draws `figure` on `root` and flushes it to `path`.
fn render<DB: DrawingBackend>(path: &Path, root: DrawingArea<DB, Shift>, figure: &impl Figure) -> Result<(), PlotError>
where
    DB::ErrorType: 'static,
{
    figure
        .draw(&root)
        .and_then(|()| root.present().map_err(save_failed))
        .map_err(|message| PlotError::Write { path: path.to_path_buf(), message })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_png_cut_short_is_refused() {
        let dir = std::env::temp_dir().join(format!("catflip-png-written-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temporary folder");
        struct Blank;
        impl Figure for Blank {
            fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
                root.fill(&WHITE).map_err(failed)
            }
        }
        let files = write_png_svg(&dir, "blank", &Blank).expect("written");
        let png = &files[0];
        assert_eq!(png_written(png), Ok(()));
        // What a failed last flush leaves: the file without its buffered tail.
        let bytes = std::fs::read(png).expect("readable");
        std::fs::write(png, &bytes[..bytes.len() - 5]).expect("writable");
        assert!(png_written(png).is_err_and(|m| m.contains("not written whole")));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
