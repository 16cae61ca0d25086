//! The plain values the conceptual map is asked about: the caller's ids of rooms, places,
//! placeholders and landmarks, the locations objects are searched in, and what is known of a
//! placeholder. Both the map and the placeholder hypotheses use them; neither owns them.

use avs_format::knowledge::Relation;

/// A room of the place map (the caller's id).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
pub struct RoomId(pub u64);
/// A place of the place map (the caller's id).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
pub struct PlaceId(pub u64);
/// A placeholder (frontier place) of the place map (the caller's id).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
pub struct PlaceholderId(pub u64);
/// A landmark object instance (table, counter, shelf) found in a room.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
pub struct LandmarkId(pub u64);

/// A location objects are searched in (the location hierarchy of Aydemir et al. 2011, §III-A).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
pub enum Location {
    /// A whole room, including every known landmark location in it (rates add, eq. 2).
    Room(RoomId),
    /// In / on one landmark instance.
    Landmark(LandmarkId, Relation),
}

/// What is known about a placeholder.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Placeholder {
    /// The room the placeholder hangs off.
    pub room: RoomId,
    /// The unknown open area behind it, m².
    pub open_area_m2: f64,
    /// Distance to the nearest door hypothesis, m, if there is one.
    pub door_distance_m: Option<f64>,
}
