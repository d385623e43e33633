//! Command-line parsers of the library types that clap does not know (the libraries stay free of
//! clap: their names live in one place, the type's own `name`).

use clap::builder::{PossibleValuesParser, TypedValueParser};
use vigil_service::recording::ChannelSet;

/// `raw`, `raw+fused` or `all`: a [`ChannelSet`] (its names are listed in `--help`).
pub fn channel_set() -> impl TypedValueParser<Value = ChannelSet> {
    PossibleValuesParser::new(ChannelSet::ALL.map(ChannelSet::name))
        .try_map(|name| ChannelSet::from_name(&name).ok_or("not a channel set"))
}
