//! afl target `uai`: see `avs_fuzz::uai`.

fn main() {
    afl::fuzz!(|data: &[u8]| avs_fuzz::uai(data));
}
