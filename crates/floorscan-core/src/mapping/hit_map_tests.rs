//! Tests of the `hit_map` module.

use super::*;

fn disc(r: i64) -> Vec<(i64, i64)> {
    let mut v = Vec::new();
    for dj in -r..=r {
        for di in -r..=r {
            if di * di + dj * dj <= r * r {
                v.push((di, dj));
            }
        }
    }
    v
}

#[test]
fn only_points_far_from_stored_hits_are_stored_and_counts_saturate() {
    let n = 40;
    let mut map = HitMap::new(n, 0.1, (0.0, 0.0), 3.0, disc(2), vec![(0, 0, 1.0)]).unwrap();
    let mut hits = vec![0u8; n * n];
    let pose = Pose2::new(1.0, 1.0, 0.0);
    assert_eq!(
        map.insert(&mut hits, &[[0.55, 0.55]], pose, true, None)
            .unwrap(),
        1
    );
    assert_eq!(hits[15 * n + 15], 1);
    // within two cells of it: not new; three cells away: new
    let pts = [[0.75, 0.55], [0.85, 0.55], [f64::NAN, 0.0], [5.0, 0.0]];
    assert_eq!(map.insert(&mut hits, &pts, pose, true, None).unwrap(), 1);
    assert_eq!(hits[15 * n + 18], 1);
    assert_eq!(hits[15 * n + 17], 0);
    // every point, the same cell 300 times: 255
    let many = vec![[0.55, 0.55]; 300];
    assert_eq!(
        map.insert(&mut hits, &many, pose, false, None).unwrap(),
        300
    );
    assert_eq!(hits[15 * n + 15], 255);
}

#[test]
fn new_hits_raise_the_field_to_their_stamp() {
    let n = 20;
    let stamp = vec![(0, 0, 1.0f32), (1, 0, 0.5), (-1, 0, 0.5)];
    let mut map = HitMap::new(n, 1.0, (0.0, 0.0), 100.0, vec![], stamp).unwrap();
    let mut hits = vec![0u8; n * n];
    let mut values = vec![0.7f32; 4 * 3];
    let field = FieldMut {
        values: &mut values,
        width: 4,
        height: 3,
        i0: 5,
        j0: 5,
    };
    map.insert(&mut hits, &[[6.5, 6.5]], Pose2::IDENTITY, true, Some(field))
        .unwrap();
    // cell (6, 6) is field cell (1, 1): 1.0 there, its neighbours keep 0.7 > 0.5
    assert_eq!(values[4 + 1], 1.0);
    assert_eq!(values[4], 0.7);
    assert_eq!(values[4 + 2], 0.7);
}

#[test]
fn bad_arguments_are_errors() {
    assert!(HitMap::new(0, 0.1, (0.0, 0.0), 3.0, vec![], vec![]).is_err());
    assert!(HitMap::new(10, 0.0, (0.0, 0.0), 3.0, vec![], vec![]).is_err());
    assert!(HitMap::new(10, 0.1, (f64::NAN, 0.0), 3.0, vec![], vec![]).is_err());
    assert!(HitMap::new(10, 0.1, (0.0, 0.0), 3.0, vec![(11, 0)], vec![]).is_err());
    let mut map = HitMap::new(10, 0.1, (0.0, 0.0), 3.0, vec![], vec![]).unwrap();
    assert!(map
        .insert(&mut [0u8; 99], &[], Pose2::IDENTITY, false, None)
        .is_err());
    let mut v = vec![0.0f32; 5];
    let f = FieldMut {
        values: &mut v,
        width: 2,
        height: 2,
        i0: 0,
        j0: 0,
    };
    assert!(map
        .insert(&mut [0u8; 100], &[], Pose2::IDENTITY, false, Some(f))
        .is_err());
}
