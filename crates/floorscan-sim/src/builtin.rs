//! Built-in worlds, loadable by name. Their files (crates/floorscan-sim/worlds/*.toml) are
//! examples of the world file format too.

use crate::error::{invalid_option, Result};
use crate::world::World;
use crate::world_file::parse_world;

/// (name, file text) of every built-in world.
pub const BUILTIN_WORLDS: [(&str, &str); 4] = [
    ("corridor", include_str!("../worlds/corridor.toml")),
    ("room", include_str!("../worlds/room.toml")),
    ("lab", include_str!("../worlds/lab.toml")),
    ("tiles", include_str!("../worlds/tiles.toml")),
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
        .ok_or_else(|| invalid_option("world", format!("no built-in world {name:?} (known: {:?})", builtin_names())))?;
    parse_world(text, &format!("built-in world {name:?}"))
}
