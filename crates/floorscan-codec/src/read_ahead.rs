//! PNG files read and decoded ahead of their consumer, in order, on threads of their own: the
//! consumer (the Python frame loop) never waits for the GIL-free decoding it could overlap, and
//! no Python runs per frame on the decoding side.
//!
//! Worker `k` of `n` decodes files `k, k + n, k + 2n, ...` into its own bounded queue; the
//! consumer takes file `i` from queue `i % n`, so frames come out in file order and at most
//! `depth` decoded frames wait in memory (plus one per worker being decoded).

use std::path::PathBuf;
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::thread::JoinHandle;

use crate::error::{one_line, Error, Result};
use crate::pixels::DecodedImage;
use crate::png::{decode_png, is_png};

/// Most bytes a PNG file of `max_pixels` pixels can reasonably take: its raw samples (up to 8
/// bytes a pixel, plus a filter byte a row) stored without compression, twice over, plus 64 MiB
/// of ancillary chunks. Larger files are left to the caller's general reader, unread here.
pub fn max_png_file_bytes(max_pixels: u64) -> u64 {
    max_pixels.saturating_mul(16).saturating_add(64 << 20)
}

/// What the read-ahead made of one file: its grey pixels, or nothing (not a PNG, unreadable,
/// too large, damaged): the caller then reads that file itself with its general reader, which
/// reports any error in its own words.
pub type Ahead = Option<DecodedImage>;

/// Decoding of a list of PNG files, ahead of the consumer, in order.
pub struct ReadAhead {
    queues: Vec<Receiver<Ahead>>,
    workers: Vec<JoinHandle<()>>,
    next: usize,
    total: usize,
}

impl ReadAhead {
    /// Starts `threads` (>= 1) workers decoding `paths` to grey (as
    /// [`DecodedImage::into_grey`]) with at most `depth` (>= 1) decoded frames waiting.
    pub fn new(paths: Vec<PathBuf>, max_pixels: u64, depth: usize, threads: usize) -> Result<Self> {
        let threads = threads.clamp(1, paths.len().max(1));
        let per_queue = depth.div_ceil(threads).max(1);
        let total = paths.len();
        let mut queues = Vec::with_capacity(threads);
        let mut workers = Vec::with_capacity(threads);
        for k in 0..threads {
            let mine: Vec<PathBuf> = paths.iter().skip(k).step_by(threads).cloned().collect();
            let (tx, rx) = sync_channel(per_queue);
            let worker = std::thread::Builder::new()
                .name(format!("floorscan-png-{k}"))
                .spawn(move || decode_all(mine, max_pixels, tx))
                .map_err(|e| Error::Read {
                    reason: one_line(format!("cannot start a decoding thread: {e}")),
                })?;
            queues.push(rx);
            workers.push(worker);
        }
        Ok(Self {
            queues,
            workers,
            next: 0,
            total,
        })
    }

    /// Number of files.
    pub fn len(&self) -> usize {
        self.total
    }

    /// Whether there are no files at all.
    pub fn is_empty(&self) -> bool {
        self.total == 0
    }

    /// The next file's result (blocks until it is decoded), or None after the last file.
    pub fn next_frame(&mut self) -> Option<Ahead> {
        if self.next >= self.total {
            return None;
        }
        let queue = &self.queues[self.next % self.queues.len()];
        self.next += 1;
        // A worker that stopped early (it cannot: it only sends) leaves the file to the caller.
        Some(queue.recv().unwrap_or(None))
    }
}

impl Drop for ReadAhead {
    /// Stops the workers: their next send fails once the queues are gone.
    fn drop(&mut self) {
        self.queues.clear();
        for worker in self.workers.drain(..) {
            let _ = worker.join();
        }
    }
}

fn decode_all(paths: Vec<PathBuf>, max_pixels: u64, out: SyncSender<Ahead>) {
    for path in paths {
        if out.send(decode_file(&path, max_pixels)).is_err() {
            return; // the consumer is gone
        }
    }
}

fn decode_file(path: &PathBuf, max_pixels: u64) -> Ahead {
    let size = std::fs::metadata(path).ok()?.len();
    if size > max_png_file_bytes(max_pixels) {
        return None;
    }
    let data = std::fs::read(path).ok()?;
    if !is_png(&data) {
        return None;
    }
    decode_png(&data, max_pixels)
        .ok()
        .map(DecodedImage::into_grey)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pixels::Samples;

    fn png(value: u8) -> Vec<u8> {
        let mut out = Vec::new();
        {
            let mut enc = ::png::Encoder::new(&mut out, 3, 2);
            enc.set_color(::png::ColorType::Grayscale);
            enc.set_depth(::png::BitDepth::Eight);
            enc.write_header()
                .unwrap()
                .write_image_data(&[value; 6])
                .unwrap();
        }
        out
    }

    fn folder(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "floorscan-read-ahead-{name}-{}",
            std::process::id()
        ));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn frames_come_in_file_order_whatever_the_threads() {
        let dir = folder("order");
        let paths: Vec<PathBuf> = (0..23u8)
            .map(|i| {
                let p = dir.join(format!("{i}.png"));
                std::fs::write(&p, png(i * 10)).unwrap();
                p
            })
            .collect();
        for threads in [1, 2, 3, 8, 40] {
            for depth in [1, 4] {
                let mut ahead = ReadAhead::new(paths.clone(), 100, depth, threads).unwrap();
                assert_eq!(ahead.len(), 23);
                for i in 0..23u8 {
                    let img = ahead.next_frame().unwrap().unwrap();
                    assert_eq!(img.samples, Samples::U8(vec![i * 10; 6]));
                }
                assert!(ahead.next_frame().is_none());
            }
        }
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn files_it_cannot_decode_are_left_to_the_caller_in_their_place() {
        let dir = folder("bad");
        let good = dir.join("good.png");
        std::fs::write(&good, png(7)).unwrap();
        let text = dir.join("text.png");
        std::fs::write(&text, b"not a png").unwrap();
        let cut = dir.join("cut.png");
        std::fs::write(&cut, &png(7)[..40]).unwrap();
        let paths = vec![good.clone(), text, dir.join("missing.png"), cut, good];
        let mut ahead = ReadAhead::new(paths, 6, 2, 2).unwrap();
        let got: Vec<bool> = std::iter::from_fn(|| ahead.next_frame())
            .map(|a| a.is_some())
            .collect();
        assert_eq!(got, vec![true, false, false, false, true]);
        // Over the pixel limit: left to the caller too.
        let mut ahead = ReadAhead::new(vec![dir.join("good.png")], 5, 1, 1).unwrap();
        assert!(ahead.next_frame().unwrap().is_none());
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn dropping_it_early_stops_the_workers() {
        let dir = folder("drop");
        let p = dir.join("a.png");
        std::fs::write(&p, png(1)).unwrap();
        let mut ahead = ReadAhead::new(vec![p; 1000], 6, 4, 2).unwrap();
        assert!(ahead.next_frame().unwrap().is_some());
        drop(ahead); // joins the workers: returns only if they stopped
        assert!(ReadAhead::new(Vec::new(), 6, 4, 2)
            .unwrap()
            .next_frame()
            .is_none());
        std::fs::remove_dir_all(dir).unwrap();
    }
}
