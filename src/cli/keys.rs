//! `drillopt keys`: the problem-file key reference (every scalar key and law parameter with its
//! unit, admissible range, default and meaning), as Markdown on standard output; `docs/keys.md`
//! is this output.

use clap::Args;
use std::io::Write;

#[derive(Debug, Args)]
pub struct KeysArgs {}

pub fn run(_args: &KeysArgs) -> anyhow::Result<()> {
    let text = crate::problem::reference::markdown();
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())?;
    out.flush()?;
    Ok(())
}
