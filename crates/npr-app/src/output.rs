//! Output files written all-or-nothing: every file goes to a temporary name beside its
//! destination and is renamed over it only when complete, so a failed command never
//! leaves a partial image, GIF, CSV or JSON behind (and never clobbers an older good one
//! with half a file).

use crate::AppError;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// The temporary name used while `path` is written.
pub fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    path.with_file_name(format!(".{name}.{}.partial", std::process::id()))
}

/// Writes `bytes` to `path` atomically.
///
/// # Errors
/// [`AppError::Io`] naming `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), AppError> {
    write_with(path, |f| {
        f.write_all(bytes).map_err(|e| AppError::io(path, e))
    })
}

/// Creates a temporary file beside `path`, lets `write` fill it, then renames it over
/// `path`. On any error the temporary file is removed.
///
/// # Errors
/// What `write` returns, or [`AppError::Io`] naming `path`.
pub fn write_with(
    path: &Path,
    write: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> Result<(), AppError>,
) -> Result<(), AppError> {
    // A destination that exists but is not a regular file (`/dev/null`, `/dev/stdout`, a
    // FIFO) is written in place: renaming over it would replace the device.
    if std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir()) {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(|e| AppError::io(path, e))?;
        let mut out = std::io::BufWriter::new(file);
        write(&mut out)?;
        return out.flush().map_err(|e| AppError::io(path, e));
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| AppError::io(dir, e))?;
    }
    let tmp = temp_path(path);
    let result = (|| {
        let file = std::fs::File::create(&tmp).map_err(|e| AppError::io(path, e))?;
        let mut out = std::io::BufWriter::new(file);
        write(&mut out)?;
        out.flush().map_err(|e| AppError::io(path, e))?;
        drop(out);
        std::fs::rename(&tmp, path).map_err(|e| AppError::io(path, e))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Encodes `image` as PNG into `path`, atomically.
///
/// # Errors
/// [`AppError::Io`] or [`AppError::Encode`].
pub fn save_png(path: &Path, image: &image::RgbaImage) -> Result<(), AppError> {
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .map_err(|e| AppError::Encode {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
    write_atomic(path, &bytes)
}

/// Encodes `frames` as a looping GIF (`delay_ms` per frame) into `path`, atomically.
///
/// # Errors
/// [`AppError::Io`] or [`AppError::Encode`].
pub fn save_gif(path: &Path, frames: &[image::RgbaImage], delay_ms: u32) -> Result<(), AppError> {
    let encode_err = |e: image::ImageError| AppError::Encode {
        path: path.to_path_buf(),
        reason: e.to_string(),
    };
    write_with(path, |out| {
        let mut enc = image::codecs::gif::GifEncoder::new_with_speed(out, 10);
        enc.set_repeat(image::codecs::gif::Repeat::Infinite)
            .map_err(encode_err)?;
        for f in frames {
            let frame = image::Frame::from_parts(
                f.clone(),
                0,
                0,
                image::Delay::from_numer_denom_ms(delay_ms, 1),
            );
            enc.encode_frame(frame).map_err(encode_err)?;
        }
        Ok(())
    })
}

/// The path of frame `i` of a turntable written as separate images: `stem_0007.png`
/// beside `out`.
pub fn frame_path(out: &Path, i: usize) -> PathBuf {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "frame".into());
    out.with_file_name(format!("{stem}_{i:04}.png"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_nothing_and_keeps_the_old_file() {
        let dir = std::env::temp_dir().join(format!("npr-out-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.txt");
        std::fs::write(&path, b"old").unwrap();
        let r = write_with(&path, |f| {
            f.write_all(b"half").map_err(|e| AppError::io(&path, e))?;
            Err(AppError::Usage("stop".into()))
        });
        assert!(r.is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        assert!(!temp_path(&path).exists());
        write_atomic(&path, b"new").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn devices_are_written_in_place_not_replaced() {
        let null = Path::new("/dev/null");
        write_atomic(null, b"discarded").unwrap();
        let meta = std::fs::metadata(null).unwrap();
        assert!(!meta.is_file(), "/dev/null was replaced by a regular file");
    }

    #[test]
    fn frame_paths_number_the_frames() {
        assert_eq!(
            frame_path(Path::new("out/bunny.png"), 7),
            PathBuf::from("out/bunny_0007.png")
        );
    }
}
