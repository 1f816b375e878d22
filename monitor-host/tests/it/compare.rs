//! `sds compare`: paired intervals, verdicts, the gate and what the tables and page show.
