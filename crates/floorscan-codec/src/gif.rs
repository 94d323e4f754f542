//! An animated GIF written frame by frame on a thread of its own (the `gif` crate's LZW), so
//! the producer only copies each frame's palette indices into a bounded queue.
//!
//! Every frame shares one global palette of up to 256 RGB colours (no per-frame quantisation:
//! the caller draws in palette indices), loops forever and shows for `delay_cs` centiseconds.
//!
//! Frames are stored with *literal* LZW codes (every index its own 9-bit code, a clear code
//! every 254 codes, so the code width never grows): a valid GIF that every decoder reads, about
//! 20 times cheaper to write than LZW compression (0.1 ms instead of 1.5-2.7 ms for 320 x 240
//! here), for files about 1.1 x the pixel count in bytes. Camera frames barely compress with
//! LZW anyway (Pillow's GIFs of the same overlays: 0.8 x).

use std::io::Write;
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::thread::JoinHandle;

use gif::{Encoder, Frame, Repeat};

use crate::error::{one_line, Error, Result};

/// Frames queued for the encoder thread at most (memory: this many frames; enough that a
/// starved encoder thread catches up while the producer waits for input, not the reverse).
pub const GIF_QUEUE_FRAMES: usize = 32;

fn encode_error(e: impl std::fmt::Display) -> Error {
    Error::Encode {
        format: "GIF",
        reason: one_line(e),
    }
}

/// An animated GIF being written to `W` by a background thread.
pub struct GifStream<W: Write + Send + 'static> {
    width: u16,
    height: u16,
    queue: Option<SyncSender<Vec<u8>>>,
    worker: Option<JoinHandle<Result<W>>>,
}

impl<W: Write + Send + 'static> GifStream<W> {
    /// Writes the header and the global `palette` (`[r, g, b, ...]`, 1 to 256 colours) of a
    /// `width` x `height` animation and starts the encoder thread.
    pub fn new(out: W, width: usize, height: usize, palette: &[u8], delay_cs: u16) -> Result<Self> {
        let size = |n: usize, what: &str| {
            u16::try_from(n).ok().filter(|&v| v > 0).ok_or_else(|| {
                Error::InvalidFrame(format!("GIF {what} must be 1..=65535, got {n}"))
            })
        };
        let (w, h) = (size(width, "width")?, size(height, "height")?);
        if palette.is_empty() || !palette.len().is_multiple_of(3) || palette.len() > 768 {
            return Err(Error::InvalidFrame(format!(
                "GIF palette must hold 1..=256 RGB colours (3 bytes each), got {} bytes",
                palette.len()
            )));
        }
        let mut encoder = Encoder::new(out, w, h, palette).map_err(encode_error)?;
        encoder.set_repeat(Repeat::Infinite).map_err(encode_error)?;
        let (tx, rx) = sync_channel(GIF_QUEUE_FRAMES);
        let worker = std::thread::Builder::new()
            .name("floorscan-gif".into())
            .spawn(move || encode_frames(encoder, rx, w, h, delay_cs))
            .map_err(encode_error)?;
        Ok(Self {
            width: w,
            height: h,
            queue: Some(tx),
            worker: Some(worker),
        })
    }

    /// Queues one frame of `width x height` palette indices, row-major (blocks while
    /// [`GIF_QUEUE_FRAMES`] are waiting). An error of the encoder thread is returned here or
    /// by [`GifStream::finish`].
    pub fn push(&mut self, indices: Vec<u8>) -> Result<()> {
        let expected = self.width as usize * self.height as usize;
        if indices.len() != expected {
            return Err(Error::InvalidFrame(format!(
                "GIF frame must have {} x {} = {expected} indices, got {}",
                self.width,
                self.height,
                indices.len()
            )));
        }
        let sent = self.queue.as_ref().map(|q| q.send(indices).is_ok());
        if sent == Some(true) {
            return Ok(());
        }
        // The encoder thread stopped: its error says why.
        self.finish_inner()
            .and(Err(encode_error("the encoder stopped")))
    }

    /// Writes the trailer and returns the writer once every queued frame is encoded.
    pub fn finish(mut self) -> Result<W> {
        self.finish_inner()
    }

    fn finish_inner(&mut self) -> Result<W> {
        self.queue = None; // the worker ends once the queue is drained
        let worker = self
            .worker
            .take()
            .ok_or_else(|| encode_error("already finished"))?;
        worker
            .join()
            .map_err(|_| encode_error("the encoder thread panicked"))?
    }
}

impl<W: Write + Send + 'static> Drop for GifStream<W> {
    fn drop(&mut self) {
        self.queue = None;
        if let Some(worker) = self.worker.take() {
            let _ = worker.join();
        }
    }
}

fn encode_frames<W: Write>(
    mut encoder: Encoder<W>,
    frames: Receiver<Vec<u8>>,
    width: u16,
    height: u16,
    delay_cs: u16,
) -> Result<W> {
    let mut lzw = Vec::new();
    for indices in frames {
        literal_lzw(&indices, &mut lzw);
        let frame = Frame {
            width,
            height,
            delay: delay_cs,
            buffer: lzw.as_slice().into(),
            ..Frame::default()
        };
        encoder
            .write_lzw_pre_encoded_frame(&frame)
            .map_err(encode_error)?;
    }
    encoder.into_inner().map_err(encode_error)
}

/// LZW minimum code size of the literal encoding: 8 (any byte is a literal code).
const MIN_CODE_SIZE: u8 = 8;
/// Codes between clear codes: a decoder's table then reaches 258 + 253 = 511 entries, below
/// the 512 at which the code width would grow to 10 bits.
const CODES_PER_CLEAR: usize = (1 << MIN_CODE_SIZE) - 2;

/// `indices` as GIF image data of literal 9-bit codes (LSB first): the minimum code size byte,
/// then a clear code before every [`CODES_PER_CLEAR`] indices and an end code. Into `out`
/// (cleared first).
fn literal_lzw(indices: &[u8], out: &mut Vec<u8>) {
    const CLEAR: u64 = 1 << MIN_CODE_SIZE;
    const END: u64 = CLEAR + 1;
    const WIDTH: u32 = MIN_CODE_SIZE as u32 + 1;
    out.clear();
    out.reserve(8 + (indices.len() + indices.len() / CODES_PER_CLEAR + 2) * 9 / 8);
    out.push(MIN_CODE_SIZE);
    // Codes gather in a 64-bit register and leave it 32 bits at a time.
    let (mut bits, mut count) = (0u64, 0u32);
    let mut put = |code: u64, out: &mut Vec<u8>| {
        bits |= code << count;
        count += WIDTH;
        if count >= 32 {
            out.extend_from_slice(&(bits as u32).to_le_bytes());
            bits >>= 32;
            count -= 32;
        }
    };
    for run in indices.chunks(CODES_PER_CLEAR) {
        put(CLEAR, out);
        for &i in run {
            put(i as u64, out);
        }
    }
    put(END, out);
    let tail = count.div_ceil(8) as usize; // the last partial byte's padding bits are ignored
    out.extend_from_slice(&bits.to_le_bytes()[..tail]);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decode(bytes: &[u8]) -> (Vec<Vec<u8>>, Vec<u8>, u16) {
        let mut opts = gif::DecodeOptions::new();
        opts.set_color_output(gif::ColorOutput::Indexed);
        let mut d = opts.read_info(bytes).unwrap();
        let palette = d.global_palette().unwrap().to_vec();
        let mut frames = Vec::new();
        let mut delay = 0;
        while let Some(f) = d.read_next_frame().unwrap() {
            delay = f.delay;
            frames.push(f.buffer.to_vec());
        }
        (frames, palette, delay)
    }

    #[test]
    fn frames_round_trip_through_a_gif_decoder() {
        let palette: Vec<u8> = (0..=255u8).flat_map(|g| [g, g, g]).collect();
        let mut s = GifStream::new(Vec::new(), 5, 3, &palette, 10).unwrap();
        let a: Vec<u8> = (0..15).collect();
        let b: Vec<u8> = (0..15).map(|i| 255 - i).collect();
        s.push(a.clone()).unwrap();
        s.push(b.clone()).unwrap();
        let bytes = s.finish().unwrap();
        assert!(bytes.starts_with(b"GIF89a") && bytes.ends_with(b";"));
        let (frames, pal, delay) = decode(&bytes);
        assert_eq!(frames, vec![a, b]);
        assert_eq!(pal, palette);
        assert_eq!(delay, 10);
    }

    #[test]
    fn literal_codes_decode_to_every_index_over_many_clear_codes() {
        // 97 x 53 = 5141 pixels: 21 clear codes; every byte value, in a scrambled order.
        let (w, h) = (97, 53);
        let frame: Vec<u8> = (0..w * h).map(|i| (i * 7919 % 256) as u8).collect();
        let palette: Vec<u8> = (0..=255u8).flat_map(|g| [g, 255 - g, g / 2]).collect();
        let mut s = GifStream::new(Vec::new(), w, h, &palette, 5).unwrap();
        for _ in 0..3 {
            s.push(frame.clone()).unwrap();
        }
        let bytes = s.finish().unwrap();
        let (frames, _, delay) = decode(&bytes);
        assert_eq!(frames, vec![frame.clone(), frame.clone(), frame]);
        assert_eq!(delay, 5);
        // 9 bits per code: the pixels, a clear code per 254, the end code (+ headers).
        let codes = w * h + (w * h).div_ceil(CODES_PER_CLEAR) + 1;
        assert!(bytes.len() < 3 * (codes * 9 / 8 + 64) + 1000);
    }

    #[test]
    fn literal_codes_are_nine_bits_lsb_first() {
        // min code size 8; clear (256), 1, 2, end (257), each 9 bits, LSB first.
        let mut out = Vec::new();
        literal_lzw(&[1, 2], &mut out);
        let mut bits: u64 = 0;
        for (k, code) in [256u64, 1, 2, 257].iter().enumerate() {
            bits |= code << (9 * k);
        }
        let want: Vec<u8> = bits.to_le_bytes()[..5].to_vec(); // 36 bits -> 5 bytes
        assert_eq!(out[0], 8);
        assert_eq!(&out[1..], &want[..]);
    }

    #[test]
    fn wrong_sizes_and_palettes_are_refused() {
        let grey = [0u8, 0, 0, 255, 255, 255];
        assert!(GifStream::new(Vec::new(), 0, 3, &grey, 10).is_err());
        assert!(GifStream::new(Vec::new(), 70000, 3, &grey, 10).is_err());
        assert!(GifStream::new(Vec::new(), 2, 2, &[0, 0], 10).is_err());
        assert!(GifStream::new(Vec::new(), 2, 2, &[0; 771], 10).is_err());
        let mut s = GifStream::new(Vec::new(), 2, 2, &grey, 10).unwrap();
        assert!(matches!(s.push(vec![0; 3]), Err(Error::InvalidFrame(_))));
        s.push(vec![0; 4]).unwrap();
        assert!(s.finish().is_ok());
    }

    /// A writer that fails after `left` bytes.
    struct Failing {
        left: usize,
    }

    impl Write for Failing {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            if self.left < buf.len() {
                return Err(std::io::Error::other("disk full"));
            }
            self.left -= buf.len();
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_failing_writer_is_an_encode_error_not_a_panic() {
        let grey = [0u8, 0, 0, 255, 255, 255];
        let mut s = GifStream::new(Failing { left: 100 }, 64, 64, &grey, 10).unwrap();
        let mut failed = false;
        for _ in 0..50 {
            if s.push(vec![1; 64 * 64]).is_err() {
                failed = true;
                break;
            }
        }
        let err = if failed { None } else { Some(s.finish().err()) };
        assert!(failed || matches!(err, Some(Some(Error::Encode { .. }))));
    }
}
