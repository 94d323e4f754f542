//! Fusing the edge and appearance range sensors column by column: the appearance ranger says
//! where the floor's look ends (it is not fooled by grout lines, wood grain or reflections), the
//! edge ranger places an edge to a fraction of a row and sees obstacles that look like the
//! floor (a grey wall over a grey carpet). The fused reading is the edge reading when the edge
//! ranger found its first edge within `snap_rows` of the appearance boundary (both boundary or
//! too-close) or when the appearance ranger saw nothing but floor (no boundary), and the
//! appearance reading otherwise (an edge far below an appearance boundary is floor texture).
//!
//! A frame whose floor breaks the texture assumption (more than `texture_share` of its edge
//! boundaries lie farther than `snap_rows` below an appearance boundary: grout lines, plank
//! joints, a printed pattern) also gives the appearance ranger's "only floor" columns to the
//! appearance reading where the edge ranger found a boundary, an edge in rows the ground table
//! does not cover, or an edge in its first window (too close): in such a frame an edge where
//! the floor's look does not end is the floor's own pattern (a grout line at the image's
//! bottom), not a grey obstacle on a grey floor. Elsewhere a too-close edge reading stays (the
//! robot may be touching an obstacle).

use crate::error::{Error, Result};
use crate::scan::{ColumnOutcome, Scan};

/// The share of `edge`'s boundary columns whose boundary lies more than `snap_rows` below
/// (nearer than) the appearance boundary of the same column: how much of the frame's floor
/// pattern the edge ranger took for obstacles. 0 without edge boundaries.
pub fn texture_edge_share(edge: &Scan, appearance: &Scan, snap_rows: f64) -> f64 {
    let (mut boundaries, mut below) = (0usize, 0usize);
    for (e, a) in edge.readings.iter().zip(&appearance.readings) {
        if let ColumnOutcome::Boundary { row: re, .. } = e.outcome {
            boundaries += 1;
            if let ColumnOutcome::Boundary { row: ra, .. } = a.outcome {
                below += usize::from(re - ra > snap_rows);
            }
        }
    }
    if boundaries == 0 {
        0.0
    } else {
        below as f64 / boundaries as f64
    }
}

/// Fewest columns with a boundary from both rangers for a frame to judge whether its floor
/// breaks the texture assumption.
pub const MIN_TEXTURE_EVIDENCE: usize = 3;

/// Frames in a row that may inherit a textured judgement before it lapses to plain (5 s at
/// 10 frames/s): a robot that leaves a tiled floor for a plain one whose obstacles the
/// appearance ranger cannot see would otherwise keep handing the edge ranger's boundaries to
/// "floor" for ever.
pub const TEXTURE_MEMORY_FRAMES: u32 = 50;

/// The fused ranger's judgement of the floor, carried from frame to frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TextureState {
    /// Whether the floor breaks the texture assumption.
    pub textured: bool,
    /// Frames in a row that inherited the judgement (0: the last frame made it).
    pub frames_inherited: u32,
}

impl TextureState {
    /// The state after a frame: its own judgement when it could make one (see
    /// [`frame_judgement`]), else the previous one, which lapses to plain after
    /// [`TEXTURE_MEMORY_FRAMES`] inherited frames.
    pub fn after(
        self,
        edge: &Scan,
        appearance: &Scan,
        snap_rows: f64,
        texture_share: f64,
    ) -> TextureState {
        match frame_judgement(edge, appearance, snap_rows, texture_share) {
            Some(textured) => TextureState {
                textured,
                frames_inherited: 0,
            },
            None if self.textured && self.frames_inherited < TEXTURE_MEMORY_FRAMES => {
                TextureState {
                    textured: true,
                    frames_inherited: self.frames_inherited + 1,
                }
            }
            None => TextureState::default(),
        }
    }
}

/// The frame's own judgement of whether its floor breaks the texture assumption (its
/// [`texture_edge_share`] exceeds `texture_share`, in [0, 1]; 1: never), `None` when it could
/// not show it: fewer than [`MIN_TEXTURE_EVIDENCE`] columns, or no more than `texture_share`
/// of the edge ranger's boundary columns, have an appearance boundary to compare with (the
/// appearance ranger saw floor in nearly every column, so even a floor of grout lines would
/// leave the share below the bar). [`TextureState::after`] then keeps the judgement of the
/// frames before: the floor does not change from one frame to the next.
fn frame_judgement(
    edge: &Scan,
    appearance: &Scan,
    snap_rows: f64,
    texture_share: f64,
) -> Option<bool> {
    if texture_share >= 1.0 {
        return Some(false);
    }
    let (mut boundaries, mut compared) = (0usize, 0usize);
    for (e, a) in edge.readings.iter().zip(&appearance.readings) {
        if matches!(e.outcome, ColumnOutcome::Boundary { .. }) {
            boundaries += 1;
            compared += usize::from(matches!(a.outcome, ColumnOutcome::Boundary { .. }));
        }
    }
    let could_show = compared as f64 > texture_share * boundaries as f64;
    if compared < MIN_TEXTURE_EVIDENCE || !could_show {
        return None;
    }
    Some(texture_edge_share(edge, appearance, snap_rows) > texture_share)
}

/// Fuses two scans of the same frame and columns into `out` (its buffer reused); a frame
/// whose [`texture_edge_share`] exceeds `texture_share` (in [0, 1]; 1: never) takes the
/// appearance reading where the appearance ranger saw only floor. Each frame on its own:
/// [`fuse_scans_after`] carries the decision over frames that cannot make it.
pub fn fuse_scans(
    edge: &Scan,
    appearance: &Scan,
    snap_rows: f64,
    texture_share: f64,
    out: &mut Scan,
) -> Result<()> {
    fuse_scans_after(
        edge,
        appearance,
        snap_rows,
        texture_share,
        TextureState::default(),
        out,
    )
    .map(|_| ())
}

/// As [`fuse_scans`] for a frame that follows others (`previous`: their judgement of the
/// floor, see [`TextureState::after`]); returns the state after this frame, for the next.
pub fn fuse_scans_after(
    edge: &Scan,
    appearance: &Scan,
    snap_rows: f64,
    texture_share: f64,
    previous: TextureState,
    out: &mut Scan,
) -> Result<TextureState> {
    fuse_scans_driven(
        edge,
        appearance,
        snap_rows,
        texture_share,
        previous,
        &[],
        out,
    )
}

/// As [`fuse_scans_after`], told per column (`driven_floor`, the appearance ranger's
/// `driven_floor_borders`; empty: none) the row of the border between the reference's floor
/// and floor the robot has driven over (NaN where none): an edge boundary within `snap_rows`
/// of it, where the appearance ranger saw only floor, is that floor's border (a rug's edge),
/// and the appearance reading is kept. An edge elsewhere in such a column stays an edge (an
/// obstacle of the floor's look beyond the rug).
pub fn fuse_scans_driven(
    edge: &Scan,
    appearance: &Scan,
    snap_rows: f64,
    texture_share: f64,
    previous: TextureState,
    driven_floor: &[f64],
    out: &mut Scan,
) -> Result<TextureState> {
    if !driven_floor.is_empty() && driven_floor.len() != appearance.len() {
        return Err(Error::LengthMismatch(format!(
            "driven_floor has {} entries for {} columns",
            driven_floor.len(),
            appearance.len()
        )));
    }
    if edge.len() != appearance.len()
        || edge
            .readings
            .iter()
            .zip(&appearance.readings)
            .any(|(a, b)| a.column != b.column)
    {
        return Err(Error::LengthMismatch(
            "the edge and appearance scans must sample the same columns".into(),
        ));
    }
    if !(snap_rows.is_finite() && snap_rows >= 0.0) {
        return Err(crate::error::invalid_option(
            "snap_rows",
            format!("must be finite and >= 0, got {snap_rows}"),
        ));
    }
    if !(0.0..=1.0).contains(&texture_share) {
        return Err(crate::error::invalid_option(
            "texture_share",
            format!("must be in [0, 1], got {texture_share}"),
        ));
    }
    let state = previous.after(edge, appearance, snap_rows, texture_share);
    let textured = state.textured;
    out.timestamp_s = appearance.timestamp_s;
    out.readings.clear();
    // whether the edge's row `re` in column j lies on the border of driven-over floor
    let on_border = |j: usize, re: f64| {
        driven_floor
            .get(j)
            .is_some_and(|&b| (re - b).abs() <= snap_rows)
    };
    out.readings.extend(
        edge.readings
            .iter()
            .zip(&appearance.readings)
            .enumerate()
            .map(|(j, (e, a))| {
                let agree = match (e.outcome, a.outcome) {
                    (ColumnOutcome::TooClose, ColumnOutcome::TooClose) => true,
                    (
                        ColumnOutcome::Boundary { row: re, .. },
                        ColumnOutcome::Boundary { row: ra, .. },
                    ) => (re - ra).abs() <= snap_rows,
                    (ColumnOutcome::Boundary { row, .. }, ColumnOutcome::TooClose) => {
                        (row - a.start_row).abs() <= snap_rows
                    }
                    // an edge boundary where the floor's look does not end: a grey obstacle on a
                    // grey floor, or in a textured frame the floor's pattern
                    // (not where that floor is floor the robot drove over: a rug's border)
                    (ColumnOutcome::Boundary { row, .. }, ColumnOutcome::NoBoundary { .. }) => {
                        !textured && !on_border(j, row)
                    }
                    // an edge in rows the table gives no ground (a bottom corner): as a boundary
                    (ColumnOutcome::Invalid { row: Some(_) }, ColumnOutcome::NoBoundary { .. }) => {
                        !textured
                    }
                    // a too-close edge stays (the robot may be at an obstacle already) unless
                    // the frame is textured (then a line of the pattern at the image's bottom)
                    (ColumnOutcome::TooClose, ColumnOutcome::NoBoundary { .. }) => !textured,
                    (_, ColumnOutcome::NoBoundary { .. }) => true,
                    _ => false,
                };
                if agree {
                    *e
                } else {
                    *a
                }
            }),
    );
    Ok(state)
}

#[cfg(test)]
#[path = "fusion_tests.rs"]
mod tests;
