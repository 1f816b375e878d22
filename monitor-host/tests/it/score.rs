//! `sds score`: protocols, the lateral reference, route sets and what the report says per route.
