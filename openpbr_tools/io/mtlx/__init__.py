"""MaterialX documents: the reader (``reader``, ``graph`` for following node graphs upstream of an
input), the writer (``writer``), in-place edits of a document that keep everything else byte for byte
(``patch``), and the raw XML scan for line numbers and inline suppressions (``xmlscan``)."""
