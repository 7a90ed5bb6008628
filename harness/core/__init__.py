"""The foundation below the stages: generic code every stage may use and that knows no stage
(it imports none of them). Plug-ins loaded from a file, a dotted module, an entry point or an
object (``plugins``), names and ``name:key=value`` specs as the command line gives them
(``names``), public names imported when first used (``lazy``), files written atomically
(``files``)."""
