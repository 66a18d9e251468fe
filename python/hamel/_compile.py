"""A model of your own from its Rust source: :func:`compile` builds it into an extension
module with cargo, in a cache directory keyed by the source, hamel's version and the Rust
toolchain, and returns its class; :func:`load` imports a module of models built otherwise
(a crate of your own with ``hamel_python::export_models!`` and ``maturin develop``).

The wheel carries the Rust sources of the hamel crates it was built from
(``_native.rust_sources()``), so a compiled model uses exactly the hamel of the package, with
the dependency versions of its Cargo.lock. The first build compiles those crates (and PyO3)
into a target directory shared by every model of the cache; later models build their own crate
only. A second call with the same source builds nothing.
"""

from __future__ import annotations

import hashlib
import importlib.machinery
import importlib.util
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import threading
from pathlib import Path
from typing import Dict, List, Optional, Union

from ._model import model_class
from .errors import CompileError

__all__ = ["compile", "load", "cache_directory"]

# Modules loaded in this process, by module name.
_LOADED: Dict[str, object] = {}
_LOCK = threading.Lock()

# A parameter struct of a model: `#[hamel_system]` (no arguments) on a struct, other
# attributes and doc comments possibly between.
_MODEL_STRUCT = re.compile(
    r"#\[\s*(?:hamel::)?hamel_system\s*\]\s*(?:(?:#\[[^\]]*\]|///[^\n]*|//[^\n]*)\s*)*"
    r"(?:pub(?:\s*\([^)]*\))?\s+)?struct\s+([A-Za-z_][A-Za-z0-9_]*)")


def cache_directory() -> Path:
    """Where compiled models are kept: ``$HAMEL_CACHE``, else ``$XDG_CACHE_HOME/hamel`` or
    ``~/.cache/hamel``."""
    if os.environ.get("HAMEL_CACHE"):
        return Path(os.environ["HAMEL_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "hamel"


def _toolchain() -> str:
    try:
        out = subprocess.run(["rustc", "-vV"], capture_output=True, text=True, check=True)
    except (OSError, subprocess.CalledProcessError) as e:
        raise CompileError(
            "hamel.compile needs the Rust toolchain (cargo and rustc on the PATH, from "
            f"rustup): {e}") from None
    return out.stdout


def _source_of(path_or_source: Union[str, os.PathLike]) -> (str, Optional[str]):
    """The source text and the file it came from (``None`` for source given as text)."""
    if isinstance(path_or_source, os.PathLike):
        path = os.fspath(path_or_source)
        return Path(path).read_text(encoding="utf-8"), path
    text = str(path_or_source)
    if "\n" not in text and len(text) < 4096:
        candidate = Path(text)
        if candidate.suffix == ".rs" or candidate.exists():
            if not candidate.exists():
                raise FileNotFoundError(f"hamel.compile: no file {text!r}")
            return candidate.read_text(encoding="utf-8"), text
    return text, None


def _unpack(blob: bytes, into: Path) -> None:
    """Writes the bundled sources (see the wheel's build.rs) under ``into``, leaving files
    whose contents are already those untouched, so that cargo, which compares times, rebuilds
    only the crates whose sources changed."""
    at = 0
    while at < len(blob):
        end = blob.index(b"\0", at)
        name = blob[at:end].decode("utf-8")
        (size,) = struct.unpack_from("<Q", blob, end + 1)
        start = end + 9
        content = blob[start:start + size]
        target = into / name
        if not (target.exists() and target.read_bytes() == content):
            target.parent.mkdir(parents=True, exist_ok=True)
            partial = target.with_name(target.name + f".{os.getpid()}.partial")
            partial.write_bytes(content)
            os.replace(partial, target)
        at = start + size


def _prepare(root: Path) -> None:
    """The cache's workspace for this hamel and toolchain: the bundled sources under
    ``bundle/`` (brought up to date when the wheel carries other sources: a rebuilt package of
    the same version), and the models' workspace under ``work/``."""
    from . import _native

    blob, bundle_hash = _native.rust_sources()
    done = root / "bundle" / ".complete"
    if done.exists() and done.read_text() == bundle_hash:
        return
    bundle = root / "bundle"
    _unpack(blob, bundle)
    work = root / "work"
    (work / "models").mkdir(parents=True, exist_ok=True)
    lock = bundle / "work" / "Cargo.lock"
    if lock.exists() and not (work / "Cargo.lock").exists():
        shutil.copyfile(lock, work / "Cargo.lock")
    manifest = ("# The models hamel.compile builds, one crate each, sharing one target directory.\n"
                "[workspace]\nmembers = [\"models/*\"]\nresolver = \"3\"\n\n"
                "[profile.release]\nstrip = \"symbols\"\n")
    if not (work / "Cargo.toml").exists() or (work / "Cargo.toml").read_text() != manifest:
        (work / "Cargo.toml").write_text(manifest)
    done.write_text(bundle_hash)


def _crate(module: str, source: str, models: List[str]) -> (str, str):
    manifest = f"""[package]
name = "{module.replace('_', '-')}"
version = "0.1.0"
edition = "2024"
publish = false

[lib]
name = "{module}"
path = "src/lib.rs"
crate-type = ["cdylib"]

[dependencies]
hamel = {{ path = "../../../bundle", default-features = false }}
hamel_python = {{ package = "hamel-python", path = "../../../bundle/hamel-python" }}
pyo3 = {{ version = "0.30", features = ["abi3-py39", "extension-module"] }}

[lints.rust]
dead_code = "allow"
unused_imports = "allow"
"""
    # The user's lines first and unchanged, so that rustc's line numbers are theirs.
    lib = source.rstrip("\n") + "\n\nhamel_python::export_models!(" + module + ": " + ", ".join(models) + ");\n"
    return manifest, lib


def _diagnostics(stdout: str, lib_path: str, shown_as: str, user_lines: int) -> List[dict]:
    """rustc's errors from cargo's JSON messages, their file names the user's."""
    errors = []
    for line in stdout.splitlines():
        try:
            message = json.loads(line)
        except ValueError:
            continue
        if message.get("reason") != "compiler-message":
            continue
        diagnostic = message.get("message", {})
        if diagnostic.get("level") not in ("error", "error: internal compiler error"):
            continue
        rendered = diagnostic.get("rendered") or diagnostic.get("message", "")
        rendered = rendered.replace(lib_path, shown_as)
        spans = [s for s in diagnostic.get("spans", []) if s.get("is_primary")]
        line_number = next((s.get("line_start") for s in spans if s.get("file_name", "").endswith("src/lib.rs")), None)
        errors.append({
            "message": diagnostic.get("message", ""),
            "rendered": rendered,
            "line": line_number if line_number is not None and line_number <= user_lines else None,
        })
    return errors


def _build(root: Path, module: str, source: str, models: List[str], shown_as: str,
           verbose: bool) -> Path:
    crate = root / "work" / "models" / module
    (crate / "src").mkdir(parents=True, exist_ok=True)
    manifest, lib = _crate(module, source, models)
    (crate / "Cargo.toml").write_text(manifest)
    (crate / "src" / "lib.rs").write_text(lib)
    command = ["cargo", "build", "--release", "--message-format=json", "-p",
               module.replace("_", "-")]
    env = dict(os.environ, PYO3_PYTHON=sys.executable, PYO3_BUILD_EXTENSION_MODULE="1")
    try:
        done = subprocess.run(command, cwd=root / "work", capture_output=True, text=True, env=env)
    except OSError as e:
        raise CompileError(f"hamel.compile needs cargo on the PATH: {e}") from None
    if verbose:
        sys.stderr.write(done.stderr)
    if done.returncode != 0:
        lib_path = os.path.join("models", module, "src", "lib.rs")
        diagnostics = _diagnostics(done.stdout, lib_path, shown_as, source.count("\n") + 1)
        if diagnostics:
            text = "\n".join(d["rendered"].rstrip() for d in diagnostics)
        else:
            text = done.stderr.strip()[-4000:]
        shutil.rmtree(crate, ignore_errors=True)
        raise CompileError(text, diagnostics, shown_as)
    built = root / "work" / "target" / "release" / f"lib{module}.so"
    if sys.platform == "darwin":
        built = built.with_suffix(".dylib")
    elif sys.platform == "win32":
        built = root / "work" / "target" / "release" / f"{module}.dll"
    suffix = ".pyd" if sys.platform == "win32" else ".abi3.so"
    target = root / "lib" / f"{module}{suffix}"
    target.parent.mkdir(parents=True, exist_ok=True)
    partial = target.with_name(target.name + f".{os.getpid()}.partial")
    shutil.copyfile(built, partial)
    os.replace(partial, target)
    return target


def _import(module: str, path: Path):
    # An extension module initializes once per process: one loaded already is reused.
    if module in sys.modules:
        return sys.modules[module]
    loader = importlib.machinery.ExtensionFileLoader(module, str(path))
    spec = importlib.util.spec_from_file_location(module, str(path), loader=loader)
    imported = importlib.util.module_from_spec(spec)
    loader.exec_module(imported)
    sys.modules[module] = imported
    return imported


def _classes(native_module, python_module: str) -> Dict[str, type]:
    return {name: model_class(t, python_module) for name, t in native_module.models.items()}


def compile(path_or_source: Union[str, os.PathLike], *, model: Optional[str] = None,
            verbose: bool = False):
    """Builds the model(s) of a Rust source — the same ``#[hamel_system]`` source as in
    hamel's README, given as a path or as text — into an extension module and returns the
    model's class (with several models in the source, a dict of their classes by name, or
    the one called ``model``).

    The module is built by cargo in :func:`cache_directory`, under a key made of the source,
    hamel's version (and the exact sources the wheel carries) and the toolchain (``rustc
    -vV``): a second call with the same source builds nothing. The first model built with a
    given hamel and toolchain also builds hamel and PyO3 (minutes, once); later ones build
    their own crate only. Errors in the source raise :class:`hamel.CompileError` with
    rustc's messages, pointing at the source's own lines (named by its path, or
    ``<source>``)."""
    from . import _native

    source, path = _source_of(path_or_source)
    models = _MODEL_STRUCT.findall(source)
    shown_as = path if path is not None else "<source>"
    if not models:
        raise CompileError(
            f"{shown_as}: no model found: a model's parameter struct carries #[hamel_system] "
            "(`#[hamel_system] pub struct Sleigh { pub m: f64, .. }`), and its impl block "
            "#[hamel_system(coordinates(..), ..)]", [], shown_as)
    _, bundle_hash = _native.rust_sources()
    toolchain = _toolchain()
    # One workspace (and target directory) per version and toolchain; one module per source,
    # built against the exact sources the wheel carries.
    version_key = hashlib.sha256(
        f"{_native.hamel_version}\n{toolchain}".encode()).hexdigest()[:16]
    source_key = hashlib.sha256(
        f"{version_key}\n{bundle_hash}\n{','.join(models)}\n{source}".encode()).hexdigest()[:16]
    module = f"hamel_model_{source_key}"
    root = cache_directory() / version_key
    with _LOCK:
        if module not in _LOADED:
            suffix = ".pyd" if sys.platform == "win32" else ".abi3.so"
            library = root / "lib" / f"{module}{suffix}"
            if not library.exists():
                root.mkdir(parents=True, exist_ok=True)
                _prepare(root)
                library = _build(root, module, source, models, shown_as, verbose)
            _LOADED[module] = _classes(_import(module, library), "hamel.compiled")
    classes = _LOADED[module]
    if model is not None:
        if model not in classes:
            raise KeyError(f"model: {model!r} is not among the source's models: {', '.join(classes)}")
        return classes[model]
    return next(iter(classes.values())) if len(classes) == 1 else dict(classes)


def load(module: str, path: Optional[Union[str, os.PathLike]] = None):
    """The model classes of an extension module made with ``hamel_python::export_models!``
    (a crate of your own, installed with ``maturin develop``): imported by name, or from the
    library file ``path``. Returns a dict of the classes by model name."""
    with _LOCK:
        if module not in _LOADED:
            if path is not None:
                native = _import(module, Path(path))
            else:
                native = importlib.import_module(module)
            if not hasattr(native, "models"):
                raise TypeError(f"{module} is not a module of hamel models (no `models`; "
                                "make it with hamel_python::export_models!)")
            _LOADED[module] = _classes(native, module)
    return dict(_LOADED[module])
