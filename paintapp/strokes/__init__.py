"""Stroke files: the records of the format (:mod:`.records`), reading files (:mod:`.files`) and
recording them as painted (:mod:`.recorder`)."""
