//! Built-in worlds, loadable by name. Their files (crates/floorscan-sim/worlds/*.toml) are
//! examples of the world file format too.

use crate::error::{invalid_option, Result};
use crate::world::World;
use crate::world_file::parse_world;

/// (name, file text) of every built-in world.
pub const BUILTIN_WORLDS: [(&str, &str); 6] = [
    ("corridor", include_str!("../worlds/corridor.toml")),
    ("room", include_str!("../worlds/room.toml")),
    ("lab", include_str!("../worlds/lab.toml")),
    ("tiles", include_str!("../worlds/tiles.toml")),
    ("parquet", include_str!("../worlds/parquet.toml")),
    ("patterned", include_str!("../worlds/patterned.toml")),
];

/// Names of the built-in worlds.
pub fn builtin_names() -> Vec<&'static str> {
    BUILTIN_WORLDS.iter().map(|(n, _)| *n).collect()
}

/// A built-in world by name.
pub fn builtin_world(name: &str) -> Result<World> {
    let (_, text) = BUILTIN_WORLDS
        .iter()
        .find(|(n, _)| *n == name)
        .ok_or_else(|| {
            invalid_option(
                "world",
                format!("no built-in world {name:?} (known: {:?})", builtin_names()),
            )
        })?;
    parse_world(text, &format!("built-in world {name:?}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::occupancy::{occupancy_raster, OccupancyOptions, FREE, OCCUPIED};
    use crate::odometry::OdometryNoise;
    use crate::robot::{drive, Motion, RobotOptions};
    use floorscan_core::Point2;

    #[test]
    fn every_builtin_world_parses_and_its_tour_keeps_clear_of_obstacles() {
        for name in builtin_names() {
            let w = builtin_world(name).unwrap();
            assert!(!w.tour.is_empty(), "{name} has no tour");
            let raster = occupancy_raster(&w, &OccupancyOptions::default()).unwrap();
            let motion = Motion::Waypoints {
                points: w.tour.clone(),
                repeat: true,
            };
            let tr = drive(
                w.start,
                &motion,
                &RobotOptions::default(),
                &OdometryNoise::none(),
                240.0,
                0,
            )
            .unwrap();
            let radius = 0.18; // robot base radius [m]
            for p in &tr.truth {
                assert_eq!(
                    raster.at(p.translation()),
                    FREE,
                    "{name}: robot at {p:?} is not in free space"
                );
                for k in 0..16 {
                    let a = k as f64 * std::f64::consts::TAU / 16.0;
                    let q = Point2::new(p.x + radius * a.cos(), p.y + radius * a.sin());
                    assert_ne!(
                        raster.at(q),
                        OCCUPIED,
                        "{name}: robot at {p:?} touches an obstacle"
                    );
                }
            }
        }
    }

    #[test]
    fn the_corridor_is_long_with_doorways_and_a_t_intersection() {
        let w = builtin_world("corridor").unwrap();
        let b = w.bounds();
        assert!(b.max.x - b.min.x >= 15.0);
        let raster = occupancy_raster(&w, &OccupancyOptions::default()).unwrap();
        // Doorways connect the corridor to the rooms: room centres are reachable (free).
        for room in [
            (4.0, 3.0),
            (8.0, 3.0),
            (12.0, 3.0),
            (5.5, -3.0),
            (10.5, -3.0),
        ] {
            assert_eq!(
                raster.at(Point2::new(room.0, room.1)),
                FREE,
                "room at {room:?}"
            );
        }
        // Both arms of the T are free.
        assert_eq!(raster.at(Point2::new(19.0, 5.0)), FREE);
        assert_eq!(raster.at(Point2::new(19.0, -5.0)), FREE);
        assert!(builtin_world("nowhere").is_err());
    }
}
