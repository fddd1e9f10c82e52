"""A run spread over processes: one task per scenario or variant (``tasks.py``), worker processes on
this machine (``parallel.py``, ``vc run -j N``) and a Dask cluster (``cluster.py``, ``vc run
--cluster``), each giving the report, the JUnit file and the traces of a serial run.
"""
