//! What the floor looks like: histograms of colour and of local texture learned from a reference
//! region of floor (Ulrich & Nourbakhsh 2000: appearance histograms of a reference area in front
//! of the robot; Lorigo, Brooks & Grimson 1997: brightness, colour and texture compared against
//! a bottom reference window), blended over frames so the model follows the building.
//!
//! A pixel looks like floor when the share of reference pixels whose colour lies within one bin
//! of its own (on each of the three colour axes) is at least `min_share`, and likewise for its
//! texture bin (when texture is used). Buffers are sized once: learning allocates nothing.

/// Intensity bins, 16 grey levels each (8-bit scale).
pub const INTENSITY_BINS: usize = 16;
/// Bins per chroma axis, 16 levels each, the grey axis on a bin edge, clamped at +-96.
pub const CHROMA_BINS: usize = 12;
/// Colour bins in all: intensity x chroma x chroma.
pub const COLOUR_BINS: usize = INTENSITY_BINS * CHROMA_BINS * CHROMA_BINS;
/// Texture bins: gradient magnitude of the green channel (see `appearance::gradient`), 8
/// levels each, the last bin open-ended.
pub const TEXTURE_BINS: usize = 8;

/// Colour bin of an 8-bit (r, g, b): intensity (r + g + b) / 3, chroma r - g and
/// (r + g) / 2 - b.
#[inline(always)]
pub fn colour_bin([r, g, b]: [i32; 3]) -> usize {
    let i = ((r + g + b) / 3).clamp(0, 255) as usize >> 4;
    let chroma = |c: i32| ((c + 96).clamp(0, 16 * CHROMA_BINS as i32 - 1) >> 4) as usize;
    let c1 = chroma(r - g);
    let c2 = chroma((r + g) / 2 - b);
    (i * CHROMA_BINS + c1) * CHROMA_BINS + c2
}

/// Texture bin of a gradient magnitude (8-bit scale).
#[inline(always)]
pub fn texture_bin(gradient: i32) -> usize {
    ((gradient.max(0) >> 3) as usize).min(TEXTURE_BINS - 1)
}

/// The learned floor appearance.
#[derive(Debug, Clone)]
pub struct FloorModel {
    colour_counts: Vec<u32>,
    texture_counts: [u32; TEXTURE_BINS],
    samples: u32,
    scratch: Vec<f32>,
    /// Learned share of reference pixels within one bin of each colour bin.
    colour_share: Vec<f32>,
    texture_share: [f32; TEXTURE_BINS],
    floor_colour: Vec<bool>,
    floor_texture: [bool; TEXTURE_BINS],
    frames: u64,
    /// Floor the robot drove over (samples of boundaries it later drove through): per bin, the
    /// decayed count of samples within one bin of it (as the reference's shares count).
    driven_colour: Vec<f32>,
    driven_texture: [f32; TEXTURE_BINS],
    driven_any: bool,
    /// The reference's own floor bins (before the driven-over ones are added).
    reference_colour: Vec<bool>,
    reference_texture: [bool; TEXTURE_BINS],
}

impl Default for FloorModel {
    fn default() -> Self {
        Self {
            colour_counts: vec![0; COLOUR_BINS],
            texture_counts: [0; TEXTURE_BINS],
            samples: 0,
            scratch: vec![0.0; COLOUR_BINS],
            colour_share: vec![0.0; COLOUR_BINS],
            texture_share: [0.0; TEXTURE_BINS],
            floor_colour: vec![false; COLOUR_BINS],
            floor_texture: [false; TEXTURE_BINS],
            frames: 0,
            driven_colour: vec![0.0; COLOUR_BINS],
            driven_texture: [0.0; TEXTURE_BINS],
            driven_any: false,
            reference_colour: vec![false; COLOUR_BINS],
            reference_texture: [false; TEXTURE_BINS],
        }
    }
}

impl FloorModel {
    /// Forgets everything learned (the next frame's reference is the whole model).
    pub fn reset(&mut self) {
        self.frames = 0;
        self.colour_share.fill(0.0);
        self.texture_share = [0.0; TEXTURE_BINS];
        self.floor_colour.fill(false);
        self.floor_texture = [false; TEXTURE_BINS];
        self.driven_colour.fill(0.0);
        self.driven_texture = [0.0; TEXTURE_BINS];
        self.driven_any = false;
        self.reference_colour.fill(false);
        self.reference_texture = [false; TEXTURE_BINS];
    }

    /// Adds one sample of floor the robot has driven over (a pixel of a boundary it later
    /// drove through): counted for every colour bin within one bin of it on each chroma axis
    /// and within `intensity_reach` bins on intensity, and for the texture bins within one, as
    /// the reference's shares count neighbours. Takes effect at the next [`Self::apply_driven`].
    pub fn add_driven(&mut self, colour: usize, texture: usize, intensity_reach: usize) {
        const C: usize = CHROMA_BINS;
        let (i0, a0, b0) = (colour / (C * C), (colour / C) % C, colour % C);
        let near =
            |x: usize, reach: usize, n: usize| x.saturating_sub(reach)..=(x + reach).min(n - 1);
        for i in near(i0, intensity_reach, INTENSITY_BINS) {
            for a in near(a0, 1, C) {
                for b in near(b0, 1, C) {
                    self.driven_colour[(i * C + a) * C + b] += 1.0;
                }
            }
        }
        for t in near(texture, 1, TEXTURE_BINS) {
            self.driven_texture[t] += 1.0;
        }
        self.driven_any = true;
    }

    /// Ages the driven-over samples by `decay` (a factor in (0, 1] per frame) and marks as
    /// floor, beside the reference's bins, the bins with at least `min_samples` of them.
    /// Called after [`Self::finish_frame`].
    pub fn apply_driven(&mut self, decay: f32, min_samples: f32) {
        if !self.driven_any {
            return;
        }
        let mut any = false;
        let mut age = |d: &mut f32| {
            *d *= decay;
            if *d < 1e-3 {
                *d = 0.0;
            }
            any |= *d > 0.0;
            *d >= min_samples
        };
        for ((f, r), d) in self
            .floor_colour
            .iter_mut()
            .zip(&self.reference_colour)
            .zip(self.driven_colour.iter_mut())
        {
            *f = *r | age(d);
        }
        for ((f, r), d) in self
            .floor_texture
            .iter_mut()
            .zip(&self.reference_texture)
            .zip(self.driven_texture.iter_mut())
        {
            *f = *r | age(d);
        }
        self.driven_any = any;
    }

    /// Whether any driven-over sample is remembered (else every floor bin is the reference's).
    pub fn driven_active(&self) -> bool {
        self.driven_any
    }

    /// Whether a pixel of these bins looks like floor to the reference alone (without the
    /// driven-over floor).
    #[inline(always)]
    pub fn is_reference_floor(&self, colour: usize, texture: Option<usize>) -> bool {
        self.reference_colour[colour] && texture.is_none_or(|t| self.reference_texture[t])
    }

    /// The decayed count of driven-over samples within one bin of a colour bin (tests and
    /// diagnostics).
    pub fn driven_colour(&self, colour: usize) -> f32 {
        self.driven_colour[colour]
    }

    /// Frames learned since the last reset.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// Starts collecting one frame's reference pixels.
    pub fn begin_frame(&mut self) {
        self.colour_counts.fill(0);
        self.texture_counts = [0; TEXTURE_BINS];
        self.samples = 0;
    }

    /// Adds one reference pixel.
    #[inline(always)]
    pub fn add(&mut self, colour: usize, texture: usize) {
        self.colour_counts[colour] += 1;
        self.texture_counts[texture] += 1;
        self.samples += 1;
    }

    /// Folds the frame's reference into the model: `model = rate * frame + (1 - rate) * model`
    /// (the first frame after a reset is the model), then marks the bins whose share is at least
    /// `min_share` as floor. Shares count reference pixels within one bin on each chroma axis
    /// and within `intensity_reach` bins on the intensity axis (light and shade of one floor).
    /// A frame without reference pixels leaves the model as it was.
    pub fn finish_frame(&mut self, adaptation_rate: f64, min_share: f64, intensity_reach: usize) {
        if self.samples == 0 {
            return;
        }
        let n = self.samples as f32;
        let rate = if self.frames == 0 {
            1.0
        } else {
            adaptation_rate as f32
        };
        // Box sums over +-1 bin along each colour axis (separable), into `scratch`.
        for (s, &c) in self.scratch.iter_mut().zip(&self.colour_counts) {
            *s = c as f32;
        }
        box3(
            &mut self.scratch,
            &mut self.colour_share,
            rate,
            n,
            intensity_reach,
        );
        let mut tex = [0f32; TEXTURE_BINS];
        for (b, t) in tex.iter_mut().enumerate() {
            let lo = b.saturating_sub(1);
            let hi = (b + 1).min(TEXTURE_BINS - 1);
            *t = self.texture_counts[lo..=hi].iter().sum::<u32>() as f32 / n;
        }
        for (m, t) in self.texture_share.iter_mut().zip(tex) {
            *m = rate * t + (1.0 - rate) * *m;
        }
        let min = min_share as f32;
        for ((f, r), &s) in self
            .floor_colour
            .iter_mut()
            .zip(self.reference_colour.iter_mut())
            .zip(&self.colour_share)
        {
            *r = s >= min;
            *f = *r;
        }
        for ((f, r), &s) in self
            .floor_texture
            .iter_mut()
            .zip(self.reference_texture.iter_mut())
            .zip(&self.texture_share)
        {
            *r = s >= min;
            *f = *r;
        }
        self.frames += 1;
    }

    /// Whether a pixel of these bins looks like floor (`texture: None` ignores texture).
    #[inline(always)]
    pub fn is_floor(&self, colour: usize, texture: Option<usize>) -> bool {
        self.floor_colour[colour] && texture.is_none_or(|t| self.floor_texture[t])
    }

    /// The learned share of a colour bin (for tests and diagnostics).
    pub fn colour_share(&self, colour: usize) -> f32 {
        self.colour_share[colour]
    }
}

/// `model = rate * box(counts) / n + (1 - rate) * model`, box = sum over +-1 bin on each chroma
/// axis and +-`reach` bins on the intensity axis.
fn box3(counts: &mut [f32], model: &mut [f32], rate: f32, n: f32, reach: usize) {
    const C: usize = CHROMA_BINS;
    let idx = |i: usize, a: usize, b: usize| (i * C + a) * C + b;
    let mut line = [0f32; INTENSITY_BINS];
    // Axis 2 (second chroma), then axis 1, then intensity; each pass in place via a line copy.
    for i in 0..INTENSITY_BINS {
        for a in 0..C {
            line[..C].copy_from_slice(&counts[idx(i, a, 0)..idx(i, a, 0) + C]);
            for b in 0..C {
                counts[idx(i, a, b)] = sum_near(&line[..C], b, 1);
            }
        }
        for b in 0..C {
            for (a, l) in line[..C].iter_mut().enumerate() {
                *l = counts[idx(i, a, b)];
            }
            for a in 0..C {
                counts[idx(i, a, b)] = sum_near(&line[..C], a, 1);
            }
        }
    }
    for a in 0..C {
        for b in 0..C {
            for (i, l) in line.iter_mut().enumerate() {
                *l = counts[idx(i, a, b)];
            }
            for i in 0..INTENSITY_BINS {
                let k = idx(i, a, b);
                model[k] = rate * sum_near(&line, i, reach) / n + (1.0 - rate) * model[k];
            }
        }
    }
}

#[inline(always)]
fn sum_near(line: &[f32], i: usize, reach: usize) -> f32 {
    let lo = i.saturating_sub(reach);
    let hi = (i + reach).min(line.len() - 1);
    line[lo..=hi].iter().sum()
}

#[cfg(test)]
#[path = "floor_model_tests.rs"]
mod tests;
