//! afl target `knowledge`: see `avs_fuzz::knowledge`.

fn main() {
    afl::fuzz!(|data: &[u8]| avs_fuzz::knowledge(data));
}
