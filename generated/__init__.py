"""Generated, versioned artefacts (data only). See MANIFEST.json; load through runtime.artefacts."""
