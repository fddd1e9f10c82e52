"""What is made of a run's results: golden traces (``golden.py``), the console report and JUnit
(``report.py``), the HTML page (``html_report.py``), timing diagrams (``timing.py`` says what they
show, ``diagram.py`` draws them with matplotlib).  They read results and recordings; none of them
runs a scenario or knows a worker.
"""
