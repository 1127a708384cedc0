"""Sphinx configuration of the partmesh documentation: the guide, the API
reference generated from the docstrings, and a gallery of runnable
examples (sphinx-gallery)."""

from importlib import metadata

project = "partmesh"
author = "the partmesh developers"
release = metadata.version("partmesh")
version = ".".join(release.split(".")[:2])

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.napoleon",
    "sphinx.ext.viewcode",
    "sphinx_gallery.gen_gallery",
]

autosummary_generate = True
napoleon_google_docstring = False  # (the docstrings use numpy-style sections)
#: a module documents what it defines; what it imports (a re-exported error, say) is documented where it is defined
autodoc_default_options = {"members": True, "show-inheritance": True, "ignore-module-all": True}
autodoc_typehints = "none"  # (the docstrings name what each argument is)
autodoc_member_order = "bysource"

sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "gallery",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
}

html_theme = "pydata_sphinx_theme"
html_title = f"partmesh {release}"
html_theme_options = {"navigation_with_keys": False, "show_toc_level": 2}
exclude_patterns = ["_build", "examples"]


def _plain_text_math(app, what, name, obj, options, lines):
    """The docstrings write their equations as plain text: absolute values
    and norms as |x| (not reStructuredText substitutions: every bar is
    escaped), and a block of equations as an indented block after a line
    that ends with a colon (shown as written: the colon becomes ``::``)."""
    for i, line in enumerate(lines):
        lines[i] = line.replace("\\|", "|").replace("|", "\\|")
    for i in range(len(lines) - 2):
        line, gap, block = lines[i], lines[i + 1], lines[i + 2]
        indent = len(line) - len(line.lstrip())
        if (line.rstrip().endswith(":") and not line.rstrip().endswith("::") and not line.lstrip().startswith(":")
                and not gap.strip() and block.strip() and len(block) - len(block.lstrip()) > indent):
            lines[i] = line.rstrip() + ":"


def setup(app):
    app.connect("autodoc-process-docstring", _plain_text_math)
