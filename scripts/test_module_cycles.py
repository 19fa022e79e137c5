"""The cycle gate's own check: a generated crate with a cycle between two folders (through
a re-export), one between siblings, and uses the gate must not count (comments, tests, a
folder's own module, another crate's re-export). Run: python3 scripts/test_module_cycles.py"""
import pathlib
import subprocess
import sys
import tempfile

GATE = pathlib.Path(__file__).with_name("module_cycles.py")


def crate(files):
    root = pathlib.Path(tempfile.mkdtemp()) / "toy"
    for rel, text in files.items():
        f = root / "src" / rel
        f.parent.mkdir(parents=True, exist_ok=True)
        f.write_text(text)
    return root


def gate(root):
    r = subprocess.run([sys.executable, GATE, str(root)], capture_output=True, text=True)
    return r.returncode, r.stdout


BASE = {
    "lib.rs": "mod a; mod b; mod c; mod d;\npub use other_crate::Thing;\n",
    "a/mod.rs": "mod x;\npub use x::X;\npub struct Shared;\nfn f() { x::g(); }\n",
    "a/x.rs": "use super::Shared;\nuse crate::b::y::Y;\npub struct X;\npub fn g() {}\n",
    "b/mod.rs": "pub mod y;\nmod z;\n",
    "b/y.rs": "pub struct Y;\n",
    "b/z.rs": "// crate::a::X in a comment\nfn f() -> crate::Thing { todo!() }\n",
    "c.rs": "use crate::d::D;\npub struct C;\n",
    "d.rs": "pub struct D;\n#[cfg(test)]\nmod tests {\n    use crate::c::C;\n}\n",
}


def main():
    code, out = gate(crate(BASE))
    assert code == 0, out
    folders = dict(BASE, **{"b/z.rs": "fn f() { let _ = crate::a::X; }\n"})
    code, out = gate(crate(folders))
    assert code == 1 and "cycle among a, b" in out, out
    siblings = dict(BASE, **{"d.rs": "pub struct D;\nfn g() -> crate::c::C { todo!() }\n"})
    code, out = gate(crate(siblings))
    assert code == 1 and "cycle among c, d" in out, out
    print("module_cycles.py: 3 generated crates judged as expected")


if __name__ == "__main__":
    main()
