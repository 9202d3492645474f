//! Append-only evaluation cache on disk (issue 4). Being built.
