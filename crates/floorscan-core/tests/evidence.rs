//! The evidence layer against a plain reference (the once-per-scan rule without clamping,
//! written with `cells_on_segment`), and the merge's contract: exact, order-free, equal to one
//! grid fed every scan; refusals of maps on other lattices.

use std::collections::{HashMap, HashSet};

use floorscan_core::evidence::{merge, EvidenceRaster};
use floorscan_core::grid::{CellRect, Grid};
use floorscan_core::grid_options::GridOptions;
use floorscan_core::inserter::{Inserter, InserterOptions};
use floorscan_core::log_odds::Evidence;
use floorscan_core::ray_update::Ray;
use floorscan_core::raycast::{cells_on_segment, CellIndex, FixedPoint};
use floorscan_core::{Error, Point2};

const EV: Evidence = Evidence {
    hit_nats: 0.85,
    miss_nats: -0.4,
};

fn generator(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `n` scans of random rays around `centre` (metres), crossing tile borders and zero.
fn random_scans(seed: u64, n: usize, centre: (f64, f64)) -> Vec<Vec<Ray>> {
    let mut next = generator(seed);
    (0..n)
        .map(|_| {
            let o = Point2::new(centre.0 + next() * 4.0 - 2.0, centre.1 + next() * 4.0 - 2.0);
            (0..32)
                .map(|_| {
                    let (a, r) = (next() * std::f64::consts::TAU, 0.5 + next() * 5.0);
                    Ray {
                        from: o,
                        to: Point2::new(o.x + r * a.cos(), o.y + r * a.sin()),
                        hit: next() < 0.6,
                    }
                })
                .collect()
        })
        .collect()
}

fn grid_with_evidence() -> Grid {
    let mut g = Grid::new(GridOptions::default()).unwrap();
    g.keep_evidence().unwrap();
    g
}

fn feed(g: &mut Grid, scans: &[Vec<Ray>]) {
    let mut ins = Inserter::new(InserterOptions::default()).unwrap();
    for rays in scans {
        ins.insert_rays(g, rays, EV).unwrap();
    }
}

/// Sum of increments by the once-per-scan rule, no clamp.
fn reference(g: &Grid, scans: &[Vec<Ray>]) -> HashMap<CellIndex, i64> {
    let fp = |p: Point2| {
        let (u, v) = g.to_cells(p);
        FixedPoint::from_cells(u, v).unwrap()
    };
    let mut sum: HashMap<CellIndex, i64> = HashMap::new();
    for rays in scans {
        let hits: HashSet<CellIndex> = rays
            .iter()
            .filter(|r| r.hit)
            .map(|r| fp(r.to).cell())
            .collect();
        let mut free = HashSet::new();
        for r in rays {
            free.extend(
                cells_on_segment(fp(r.from), fp(r.to))
                    .unwrap()
                    .filter(|c| !hits.contains(c)),
            );
        }
        for c in hits {
            *sum.entry(c).or_default() += 850;
        }
        for c in free {
            *sum.entry(c).or_default() -= 400;
        }
    }
    sum
}

fn raster(g: &Grid) -> EvidenceRaster {
    g.evidence_raster(g.evidence_rect().unwrap())
}

/// Same cells and values; origins equal to rounding.
fn same(a: &EvidenceRaster, b: &EvidenceRaster) {
    assert_eq!((a.width, a.height), (b.width, b.height));
    assert!(
        (a.origin_m.x - b.origin_m.x).abs() < 1e-9 && (a.origin_m.y - b.origin_m.y).abs() < 1e-9
    );
    let differing = a
        .values
        .iter()
        .zip(&b.values)
        .filter(|(x, y)| x != y)
        .count();
    assert_eq!(differing, 0, "{differing} cells differ");
}

fn value_at(r: &EvidenceRaster, c: CellIndex, lattice: &Grid) -> i32 {
    let (u, v) = lattice.to_cells(r.origin_m);
    let (col, row) = (c.x - u.round() as i32, c.y - v.round() as i32);
    if col < 0 || row < 0 || col as usize >= r.width || row as usize >= r.height {
        return 0;
    }
    r.values[row as usize * r.width + col as usize]
}

#[test]
fn evidence_is_the_unclamped_sum_of_the_once_per_scan_increments() {
    let scans = random_scans(0x1234_5678_9abc_def1, 60, (0.0, 0.0));
    let mut g = grid_with_evidence();
    feed(&mut g, &scans);
    let expected = reference(&g, &scans);
    let mut beyond_clamp = 0;
    for (c, &e) in &expected {
        assert_eq!(i64::from(g.evidence(*c)), e, "cell {c:?}");
        beyond_clamp += usize::from(!(-2000..=3500).contains(&e));
    }
    // Many cells went past the clamp: the layer really is unclamped.
    assert!(
        beyond_clamp > 100,
        "only {beyond_clamp} cells past the clamp"
    );
    let r = g.evidence_rect().unwrap();
    let nonzero = expected.values().filter(|&&v| v != 0).count();
    let mut vals = Vec::new();
    g.read_evidence_rect(r, &mut vals);
    assert_eq!(vals.iter().filter(|&&v| v != 0).count(), nonzero);
}

#[test]
fn keeping_evidence_does_not_change_the_clamped_map() {
    let scans = random_scans(77, 30, (3.0, -2.0));
    let mut with = grid_with_evidence();
    let mut without = Grid::new(GridOptions::default()).unwrap();
    feed(&mut with, &scans);
    feed(&mut without, &scans);
    let rect = without.known_rect().unwrap();
    let (mut a, mut b) = (Vec::new(), Vec::new());
    with.read_rect(rect, &mut a);
    without.read_rect(rect, &mut b);
    assert_eq!(a, b);
    assert_eq!(without.evidence(CellIndex::new(75, -50)), 0);
    assert!(with.memory_bytes() > without.memory_bytes());
}

#[test]
fn merge_is_exact_order_free_and_equals_one_grid_fed_everything() {
    let a_scans = random_scans(11, 25, (0.0, 0.0));
    let b_scans = random_scans(22, 25, (4.5, 3.0)); // another extent, overlapping
    let c_scans = random_scans(33, 10, (-6.0, 1.0));
    let (mut a, mut b, mut c, mut all) = (
        grid_with_evidence(),
        grid_with_evidence(),
        grid_with_evidence(),
        grid_with_evidence(),
    );
    feed(&mut a, &a_scans);
    feed(&mut b, &b_scans);
    feed(&mut c, &c_scans);
    feed(&mut all, &a_scans);
    feed(&mut all, &b_scans);
    feed(&mut all, &c_scans);
    let (ra, rb, rc) = (raster(&a), raster(&b), raster(&c));
    let abc = merge(&[ra.clone(), rb.clone(), rc.clone()]).unwrap();
    let cba = merge(&[rc.clone(), rb.clone(), ra.clone()]).unwrap();
    let bac = merge(&[merge(&[rb.clone(), ra.clone()]).unwrap(), rc.clone()]).unwrap();
    same(&abc, &cba);
    same(&abc, &bac);
    same(&abc, &raster(&all));
    // Cell for cell, the sum of the three.
    let rect = all.evidence_rect().unwrap();
    for y in rect.min.y..rect.max.y {
        for x in rect.min.x..rect.max.x {
            let cell = CellIndex::new(x, y);
            let sum = a.evidence(cell) + b.evidence(cell) + c.evidence(cell);
            assert_eq!(value_at(&abc, cell, &all), sum, "cell {cell:?}");
        }
    }
}

#[test]
fn clamping_once_differs_from_clamping_every_scan() {
    // One cell seen free 10 times, then occupied 5 times (and the reverse order).
    let free: Vec<Ray> = vec![Ray {
        from: Point2::new(0.02, 0.02),
        to: Point2::new(0.02, 0.02),
        hit: false,
    }];
    let hit: Vec<Ray> = vec![Ray {
        hit: true,
        ..free[0]
    }];
    let seq: Vec<Vec<Ray>> = std::iter::repeat_n(free.clone(), 10)
        .chain(std::iter::repeat_n(hit.clone(), 5))
        .collect();
    let rev: Vec<Vec<Ray>> = seq.iter().rev().cloned().collect();
    let (mut g1, mut g2) = (grid_with_evidence(), grid_with_evidence());
    feed(&mut g1, &seq);
    feed(&mut g2, &rev);
    let c = CellIndex::new(0, 0);
    // Clamping every scan: free first reaches -2000 then climbs 5 * 850 (occupied, 2250);
    // occupied first reaches 3500 then falls 10 * 400 (-500, unknown).
    assert_eq!(g1.get(c).0, 2250);
    assert_eq!(g2.get(c).0, -500);
    // The evidence is the same either way: 5 * 850 - 10 * 400, and clamped once it stays.
    assert_eq!(g1.evidence(c), 250);
    assert_eq!(g2.evidence(c), 250);
    let limits = g1.limits();
    assert_eq!(raster(&g1).clamped(limits), vec![250]);
    assert_eq!(raster(&g2).clamped(limits), vec![250]);
}

#[test]
fn maps_on_other_lattices_are_refused() {
    let r = EvidenceRaster {
        cell_size_m: 0.04,
        origin_m: Point2::new(0.0, 0.0),
        width: 2,
        height: 1,
        values: vec![1, 2],
    };
    let other_size = EvidenceRaster {
        cell_size_m: 0.05,
        ..r.clone()
    };
    assert!(matches!(
        merge(&[r.clone(), other_size]),
        Err(Error::InvalidOption {
            name: "cell_size_m",
            ..
        })
    ));
    let shifted = EvidenceRaster {
        origin_m: Point2::new(0.01, 0.0),
        ..r.clone()
    };
    let e = merge(&[r.clone(), shifted]).unwrap_err();
    assert!(matches!(e, Error::InvalidGeometry(_)) && e.to_string().contains("lattice"));
    let bad_len = EvidenceRaster {
        values: vec![1],
        ..r.clone()
    };
    assert!(matches!(
        merge(&[r.clone(), bad_len]),
        Err(Error::LengthMismatch(_))
    ));
    assert!(merge(&[]).is_err());
    // Whole cells apart (with rounding noise) is fine: offset by 3 cells in x, -1 in y.
    let moved = EvidenceRaster {
        origin_m: Point2::new(0.12 + 1e-12, -0.04),
        ..r.clone()
    };
    let m = merge(&[r.clone(), moved]).unwrap();
    assert_eq!((m.width, m.height), (5, 2));
    assert_eq!(m.values, vec![0, 0, 0, 1, 2, 1, 2, 0, 0, 0]);
    assert!((m.origin_m.y + 0.04).abs() < 1e-12);
    // Overflow of a summed cell is an error, not a wrap.
    let big = EvidenceRaster {
        values: vec![i32::MAX, 0],
        ..r.clone()
    };
    assert!(matches!(merge(&[big, r]), Err(Error::OutOfBounds(_))));
}

#[test]
fn evidence_must_be_kept_from_the_first_update() {
    let mut g = Grid::new(GridOptions::default()).unwrap();
    feed(&mut g, &random_scans(5, 1, (0.0, 0.0)));
    assert!(matches!(
        g.keep_evidence(),
        Err(Error::InvalidOption {
            name: "keep_evidence",
            ..
        })
    ));
    let empty = grid_with_evidence();
    assert!(empty.evidence_rect().is_none());
    let r = empty.evidence_raster(CellRect {
        min: CellIndex::new(0, 0),
        max: CellIndex::new(0, 0),
    });
    assert!(r.values.is_empty());
}
