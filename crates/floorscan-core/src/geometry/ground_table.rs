//! The paper's calibration lookup table (III.B): camera-centred ground points at a regular grid of
//! image points, with bilinear interpolation between them. No camera model is assumed, so any
//! lens that a calibration can fit works.
//!
//! Camera ground frame: origin on the floor below the camera, x along the camera's heading, y to
//! the left, metres (REP 103).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::pose::Point2;

/// Identifies floorscan ground table files.
pub const GROUND_TABLE_FORMAT: &str = "floorscan.ground_table";
/// The newest schema version: 2 adds the optional per-node predicted error `error_m`. A table
/// without errors is still written as version 1, so older readers keep reading it; both are read.
pub const GROUND_TABLE_VERSION: u32 = 2;
/// The oldest schema version this build reads.
pub const GROUND_TABLE_MIN_VERSION: u32 = 1;

/// Image-to-ground lookup table for images of `image_width` x `image_height` pixels.
///
/// Node (i, j) sits at pixel u = i * spacing_px, v = j * spacing_px; the nodes cover the whole
/// image (the last node may lie past its edge). A node holds a ground point or "no ground".
#[derive(Debug, Clone, PartialEq)]
pub struct GroundTable {
    image_width: usize,
    image_height: usize,
    spacing_px: usize,
    nodes_u: usize,
    nodes_v: usize,
    /// Ground points of the nodes, row-major (v outer); `None` is "no ground".
    nodes: Vec<Option<Point2>>,
    /// Predicted floor-position error of each node [m] (a calibration's error bar), row-major
    /// like `nodes`; `None` for the whole table when unknown, or for one node without ground.
    errors: Option<Vec<Option<f64>>>,
    /// Free-form provenance (source, calibration report summary). Saved with the table.
    pub metadata: BTreeMap<String, serde_json::Value>,
}

/// Largest image side a table may declare [px] (a bound on every per-row or per-column buffer).
pub const MAX_IMAGE_SIDE_PX: usize = 1 << 16;
/// Most pixels a table's image may have (2^28, e.g. 16384 x 16384).
pub const MAX_IMAGE_PIXELS: usize = 1 << 28;

/// Checks a table's declared image size and spacing against the limits above, and returns its
/// node grid size and node count with checked arithmetic (so no product can wrap).
pub fn checked_node_shape(
    image_width: usize,
    image_height: usize,
    spacing_px: usize,
) -> Result<(usize, usize, usize)> {
    if image_width < 2 || image_height < 2 {
        return Err(Error::InvalidTable(format!(
            "image must be at least 2 x 2 pixels, got {image_width} x {image_height}"
        )));
    }
    if spacing_px == 0 {
        return Err(Error::InvalidTable("spacing_px must be at least 1".into()));
    }
    let pixels = image_width.checked_mul(image_height);
    if image_width > MAX_IMAGE_SIDE_PX
        || image_height > MAX_IMAGE_SIDE_PX
        || pixels.is_none_or(|p| p > MAX_IMAGE_PIXELS)
    {
        return Err(Error::InvalidTable(format!(
            "a {image_width} x {image_height} image is larger than this build reads (sides up to {MAX_IMAGE_SIDE_PX} px, {MAX_IMAGE_PIXELS} pixels)"
        )));
    }
    let (nu, nv) = node_counts(image_width, image_height, spacing_px);
    let total = nu
        .checked_mul(nv)
        .ok_or_else(|| Error::InvalidTable(format!("{nu} x {nv} nodes overflow")))?;
    Ok((nu, nv, total))
}

/// The node grid size for an image size and spacing.
pub fn node_counts(image_width: usize, image_height: usize, spacing_px: usize) -> (usize, usize) {
    let n = |len: usize| (len.saturating_sub(1)).div_ceil(spacing_px) + 1;
    (n(image_width), n(image_height))
}

/// The bilinear interpolation at fractions (fu, fv) of a cell's nodes `[p00, p10, p01, p11]`.
#[inline(always)]
fn bilinear(fu: f64, fv: f64, [p00, p10, p01, p11]: &[Point2; 4]) -> Point2 {
    let w00 = (1.0 - fu) * (1.0 - fv);
    let w10 = fu * (1.0 - fv);
    let w01 = (1.0 - fu) * fv;
    let w11 = fu * fv;
    Point2::new(
        w00 * p00.x + w10 * p10.x + w01 * p01.x + w11 * p11.x,
        w00 * p00.y + w10 * p10.y + w01 * p01.y + w11 * p11.y,
    )
}

impl GroundTable {
    /// A table from node values (row-major, `nodes_v` rows of `nodes_u`); see [`node_counts`].
    pub fn from_nodes(
        image_width: usize,
        image_height: usize,
        spacing_px: usize,
        nodes: Vec<Option<Point2>>,
    ) -> Result<Self> {
        let (nodes_u, nodes_v, total) = checked_node_shape(image_width, image_height, spacing_px)?;
        if nodes.len() != total {
            return Err(Error::InvalidTable(format!(
                "{} x {} image at {spacing_px} px spacing needs {nodes_v} x {nodes_u} = {} nodes, got {}",
                image_width,
                image_height,
                total,
                nodes.len()
            )));
        }
        if nodes
            .iter()
            .flatten()
            .any(|p| !(p.x.is_finite() && p.y.is_finite()))
        {
            return Err(Error::InvalidTable(
                "ground points must be finite (use no-ground instead)".into(),
            ));
        }
        Ok(Self {
            image_width,
            image_height,
            spacing_px,
            nodes_u,
            nodes_v,
            nodes,
            errors: None,
            metadata: BTreeMap::new(),
        })
    }

    /// The same table with a predicted floor-position error [m] per node (row-major, one per
    /// node; NaN or `None` where unknown). Errors must be finite and >= 0 where given.
    pub fn with_errors(mut self, errors_m: &[f64]) -> Result<Self> {
        if errors_m.len() != self.nodes.len() {
            return Err(Error::LengthMismatch(format!(
                "the table has {} nodes, {} errors given",
                self.nodes.len(),
                errors_m.len()
            )));
        }
        if errors_m.iter().any(|&e| e < 0.0 || e == f64::INFINITY) {
            return Err(Error::InvalidTable(
                "node errors must be finite and >= 0 (NaN for unknown)".into(),
            ));
        }
        self.errors = Some(
            errors_m
                .iter()
                .zip(&self.nodes)
                .map(|(&e, p)| (p.is_some() && e.is_finite()).then_some(e))
                .collect(),
        );
        Ok(self)
    }

    /// Predicted floor-position errors of the nodes [m], row-major; `None` when the table
    /// carries none.
    pub fn errors(&self) -> Option<&[Option<f64>]> {
        self.errors.as_deref()
    }

    /// A table from separate x and y arrays [m]; a NaN in either marks "no ground".
    pub fn from_arrays(
        image_width: usize,
        image_height: usize,
        spacing_px: usize,
        x_m: &[f64],
        y_m: &[f64],
    ) -> Result<Self> {
        if x_m.len() != y_m.len() {
            return Err(Error::LengthMismatch(format!(
                "x has {} nodes, y has {}",
                x_m.len(),
                y_m.len()
            )));
        }
        let nodes = x_m
            .iter()
            .zip(y_m)
            .map(|(&x, &y)| (x.is_finite() && y.is_finite()).then_some(Point2::new(x, y)))
            .collect();
        Self::from_nodes(image_width, image_height, spacing_px, nodes)
    }

    /// A table by evaluating `ground_of_pixel(u, v)` at every node.
    pub fn from_fn(
        image_width: usize,
        image_height: usize,
        spacing_px: usize,
        mut ground_of_pixel: impl FnMut(f64, f64) -> Option<Point2>,
    ) -> Result<Self> {
        let (nu, nv, total) = checked_node_shape(image_width, image_height, spacing_px)?;
        let mut nodes = Vec::with_capacity(total);
        for j in 0..nv {
            for i in 0..nu {
                let p = ground_of_pixel((i * spacing_px) as f64, (j * spacing_px) as f64);
                nodes.push(p.filter(|p| p.x.is_finite() && p.y.is_finite()));
            }
        }
        Self::from_nodes(image_width, image_height, spacing_px, nodes)
    }

    pub fn image_width(&self) -> usize {
        self.image_width
    }
    pub fn image_height(&self) -> usize {
        self.image_height
    }
    pub fn spacing_px(&self) -> usize {
        self.spacing_px
    }
    /// (nodes_u, nodes_v).
    pub fn node_shape(&self) -> (usize, usize) {
        (self.nodes_u, self.nodes_v)
    }
    /// Node values, row-major.
    pub fn nodes(&self) -> &[Option<Point2>] {
        &self.nodes
    }

    /// The cell (i, j) whose four nodes surround pixel (u, v) and the fractions (fu, fv)
    /// across it; `None` outside the image.
    fn cell(&self, u: f64, v: f64) -> Option<(usize, usize, f64, f64)> {
        let max_u = (self.image_width - 1) as f64;
        let max_v = (self.image_height - 1) as f64;
        // Half a pixel of slack: a pixel's area extends 0.5 px around its centre.
        if !(u >= -0.5 && u <= max_u + 0.5 && v >= -0.5 && v <= max_v + 0.5) {
            return None;
        }
        let s = self.spacing_px as f64;
        // A power-of-two spacing divides exactly as a multiplication by its exact inverse
        // (the same value, without a division's latency).
        let (gu, gv) = if self.spacing_px.is_power_of_two() && self.spacing_px < 1 << 20 {
            let inv = f64::from_bits((1023 - self.spacing_px.trailing_zeros() as u64) << 52);
            (u.max(0.0) * inv, v.max(0.0) * inv)
        } else {
            (u.max(0.0) / s, v.max(0.0) / s)
        };
        let gu = gu.min((self.nodes_u - 1) as f64);
        let gv = gv.min((self.nodes_v - 1) as f64);
        // gu, gv >= 0 and finite here, where truncation is floor (and needs no libm call).
        let i = (gu as usize).min(self.nodes_u - 2);
        let j = (gv as usize).min(self.nodes_v - 2);
        Some((i, j, gu - i as f64, gv - j as f64))
    }

    fn node(&self, i: usize, j: usize) -> Option<Point2> {
        self.nodes[j * self.nodes_u + i]
    }

    /// The rows of image column `u` that a ranger starting at row `start_row` can place, as
    /// `(first, top)`: the lowest row at or above the start whose ground `keep` accepts (the
    /// column's near edge of view) and the highest row above it reached without a row that has
    /// none. `None` when no row at or above the start has ground. Rows between the start and
    /// `first` (an image corner the table does not trust) are the ranger's to scan but not to
    /// place.
    pub fn column_ground_rows(
        &self,
        u: f64,
        start_row: usize,
        keep: impl Fn(Point2) -> bool,
    ) -> Option<(usize, usize)> {
        let ground = |v: usize| self.lookup(u, v as f64).is_some_and(&keep);
        let first = (0..=start_row).rev().find(|&v| ground(v))?;
        let mut top = first;
        while top > 0 && ground(top - 1) {
            top -= 1;
        }
        Some((first, top))
    }

    /// Ground point [m] seen at pixel (u, v), by bilinear interpolation of the four nodes around
    /// it; `None` if any of them is "no ground" or the pixel is outside the image.
    pub fn lookup(&self, u: f64, v: f64) -> Option<Point2> {
        let (fu, fv, corners) = self.corners(u, v)?;
        Some(bilinear(fu, fv, &corners))
    }

    /// The fractions (fu, fv) across the cell around pixel (u, v) and its four nodes
    /// `[p00, p10, p01, p11]`; `None` if any is "no ground" or the pixel is outside the image.
    #[inline(always)]
    fn corners(&self, u: f64, v: f64) -> Option<(f64, f64, [Point2; 4])> {
        let (i, j, fu, fv) = self.cell(u, v)?;
        Some((
            fu,
            fv,
            [
                self.node(i, j)?,
                self.node(i + 1, j)?,
                self.node(i, j + 1)?,
                self.node(i + 1, j + 1)?,
            ],
        ))
    }

    /// The ground point at pixel (u, v), as [`Self::lookup`] gives it, and the derivatives of
    /// the bilinear interpolation of its cell there, `[dx/du, dx/dv, dy/du, dy/dv]` [m/px]
    /// (one cell's four nodes: what the finite differences of
    /// [`Self::jacobian`](crate::ground_table_inverse) give within a cell, without their two
    /// more lookups).
    pub fn lookup_with_derivatives(&self, u: f64, v: f64) -> Option<(Point2, [f64; 4])> {
        let (fu, fv, corners) = self.corners(u, v)?;
        let p = bilinear(fu, fv, &corners);
        let [p00, p10, p01, p11] = corners;
        let s = self.spacing_px as f64;
        let du = |a: f64, b: f64, c: f64, d: f64| ((1.0 - fv) * (b - a) + fv * (d - c)) / s;
        let dv = |a: f64, b: f64, c: f64, d: f64| ((1.0 - fu) * (c - a) + fu * (d - b)) / s;
        Some((
            p,
            [
                du(p00.x, p10.x, p01.x, p11.x),
                dv(p00.x, p10.x, p01.x, p11.x),
                du(p00.y, p10.y, p01.y, p11.y),
                dv(p00.y, p10.y, p01.y, p11.y),
            ],
        ))
    }

    /// Predicted floor-position error [m] at pixel (u, v): the bilinear interpolation of the
    /// four surrounding nodes' errors; `None` where the table has no ground there or carries
    /// no errors.
    pub fn lookup_error(&self, u: f64, v: f64) -> Option<f64> {
        let errors = self.errors.as_ref()?;
        let (i, j, fu, fv) = self.cell(u, v)?;
        let e = |i: usize, j: usize| errors[j * self.nodes_u + i];
        Some(
            (1.0 - fu) * (1.0 - fv) * e(i, j)?
                + fu * (1.0 - fv) * e(i + 1, j)?
                + (1.0 - fu) * fv * e(i, j + 1)?
                + fu * fv * e(i + 1, j + 1)?,
        )
    }

    /// Serialises to the documented JSON file format (see docs/formats.md).
    pub fn to_json(&self) -> String {
        let file = GroundTableFile {
            format: GROUND_TABLE_FORMAT.to_string(),
            version: if self.errors.is_some() {
                GROUND_TABLE_VERSION
            } else {
                GROUND_TABLE_MIN_VERSION
            },
            image_width: self.image_width,
            image_height: self.image_height,
            spacing_px: self.spacing_px,
            nodes_u: self.nodes_u,
            nodes_v: self.nodes_v,
            x_m: self.nodes.iter().map(|p| p.map(|p| p.x)).collect(),
            y_m: self.nodes.iter().map(|p| p.map(|p| p.y)).collect(),
            error_m: self.errors.clone(),
            metadata: self.metadata.clone(),
        };
        serde_json::to_string(&file).expect("ground table serialisation cannot fail")
    }

    /// Parses the JSON file format; another version or a damaged file is an error.
    pub fn from_json(text: &str) -> Result<Self> {
        let malformed = |reason: String| Error::Malformed {
            kind: "ground table",
            reason,
        };
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| malformed(format!("not valid JSON: {e}")))?;
        match value.get("format").and_then(|f| f.as_str()) {
            Some(GROUND_TABLE_FORMAT) => {}
            other => {
                return Err(malformed(format!(
                    "field `format` must be \"{GROUND_TABLE_FORMAT}\", got {other:?}"
                )))
            }
        }
        let version = value
            .get("version")
            .and_then(|v| v.as_u64())
            .ok_or_else(|| malformed("missing integer field `version`".into()))?;
        if !(GROUND_TABLE_MIN_VERSION as u64..=GROUND_TABLE_VERSION as u64).contains(&version) {
            return Err(Error::UnsupportedVersion {
                kind: "ground table",
                found: version.min(u32::MAX as u64) as u32,
                expected: GROUND_TABLE_VERSION,
            });
        }
        let file: GroundTableFile =
            serde_json::from_value(value).map_err(|e| malformed(e.to_string()))?;
        let (eu, ev, _) = checked_node_shape(file.image_width, file.image_height, file.spacing_px)
            .map_err(|e| malformed(e.to_string()))?;
        let expected = (eu, ev);
        if (file.nodes_u, file.nodes_v) != expected {
            return Err(malformed(format!(
                "node grid {} x {} does not match the image size and spacing (expected {} x {})",
                file.nodes_u, file.nodes_v, expected.0, expected.1
            )));
        }
        if file.x_m.len() != file.y_m.len() {
            return Err(malformed("x_m and y_m differ in length".into()));
        }
        let nodes = file
            .x_m
            .iter()
            .zip(&file.y_m)
            .map(|(x, y)| match (x, y) {
                (Some(x), Some(y)) => Some(Point2::new(*x, *y)),
                _ => None,
            })
            .collect();
        let mut table =
            Self::from_nodes(file.image_width, file.image_height, file.spacing_px, nodes)
                .map_err(|e| malformed(e.to_string()))?;
        if let Some(errors) = file.error_m {
            if version < 2 {
                return Err(malformed("field `error_m` needs version 2".into()));
            }
            if errors.len() != table.nodes.len() {
                return Err(malformed(format!(
                    "error_m has {} values for {} nodes",
                    errors.len(),
                    table.nodes.len()
                )));
            }
            let values: Vec<f64> = errors.iter().map(|e| e.unwrap_or(f64::NAN)).collect();
            table = table
                .with_errors(&values)
                .map_err(|e| malformed(e.to_string()))?;
        }
        table.metadata = file.metadata;
        Ok(table)
    }
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct GroundTableFile {
    format: String,
    version: u32,
    image_width: usize,
    image_height: usize,
    spacing_px: usize,
    nodes_u: usize,
    nodes_v: usize,
    x_m: Vec<Option<f64>>,
    y_m: Vec<Option<f64>>,
    /// Version 2: predicted floor-position error per node [m], `null` where unknown.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    error_m: Option<Vec<Option<f64>>>,
    #[serde(default)]
    metadata: BTreeMap<String, serde_json::Value>,
}

#[cfg(test)]
#[path = "ground_table_tests.rs"]
mod tests;
