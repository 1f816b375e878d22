//! The per-route stage: what each route comes to, between the replay ([`crate::pipeline`]) and
//! the aggregates ([`crate::aggregate`]). The route's [`row`] of the report, its [`penalty`]
//! re-check (docs/SCORE.md §9), its loss from DS to DS_safe per SDS factor ([`decomposition`]), its
//! Bench2Drive [`ability`] entries and [`efficiency`] (docs/SCORE.md §10.1), its [`events`] on the frame axis,
//! and the [`trace`]s of its aligned collisions (docs/SCORE.md §14.4).

pub mod ability;
pub mod decomposition;
pub mod efficiency;
pub mod events;
pub mod penalty;
pub mod protocol;
pub mod row;
pub mod trace;
