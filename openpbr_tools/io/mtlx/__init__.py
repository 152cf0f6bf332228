"""MaterialX documents: the reader (``reader``), the writer (``writer``), in-place edits of a document
that keep everything else byte for byte (``patch``), and the raw XML scan for line numbers and
inline suppressions (``xmlscan``)."""
