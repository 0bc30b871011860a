"""Run directories on object storage (``output: s3://bucket/prefix``, any fsspec URL).

The driver writes its run directory on local disk (a mirror, where commits are atomic) and a background uploader
puts each committed journal entry, then each compacted shard, the manifest and the artifacts, in the bucket
(``_sync``); a lease object keeps a second driver off the run (``_lease``); a driver on another machine starts
from the bucket's contents (``_mirror``). Readers open a remote run through a local view holding only its small
files, the Parquet shards read in place and artifacts fetched when a page or export opens them (``_view``).

Nothing is imported here: ``results._store`` reads views through ``_view``, which must not import the results
package back.
"""
