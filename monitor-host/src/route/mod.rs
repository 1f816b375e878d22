//! The per-route stage: what each route comes to, between the replay ([`crate::pipeline`]) and
//! the aggregates ([`crate::aggregate`]). The route's [`row`] of the report, its [`penalty`]
//! re-check (§8), its loss from DS to DS_safe per SDS factor ([`decomposition`]), its
//! Bench2Drive [`ability`] entries and [`efficiency`] (§8.2), its [`events`] on the frame axis,
//! and the [`trace`]s of its aligned collisions (§10.2).

pub mod ability;
pub mod decomposition;
pub mod efficiency;
pub mod events;
pub mod penalty;
pub mod protocol;
pub mod row;
pub mod trace;
