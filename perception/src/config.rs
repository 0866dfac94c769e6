//! The pipeline's one configuration: a section per stage, every field with a documented
//! default, read from the `[perception]` table of `trackd.toml`.

use serde::{Deserialize, Serialize};

/// Every threshold of the perception pipeline.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Config {}
