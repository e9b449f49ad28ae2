//! Scenes built in code, for tests and benchmarks that should not depend on files.
