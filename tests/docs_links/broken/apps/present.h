// A file the fixture names (tests/docs_links/broken/README.md).
