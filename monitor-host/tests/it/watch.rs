//! `sds watch`: rounds, the cache, the stop rule, retries and the final report.
