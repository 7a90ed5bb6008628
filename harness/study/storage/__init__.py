"""A study's results folder and what is kept in it: written atomically (``files``), owned by one
run at a time (``folder``), rows merged by key (``merge``, ``store``), every finished level made
durable (``checkpoint``), and the one digest that says which code and versions stored results are
valid for (``digest``)."""
