//! Hostile and careless input: markup in names, planted links, huge counts, interrupted writes.
