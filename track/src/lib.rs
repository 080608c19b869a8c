//! Track irregularities and wheel hunting.
