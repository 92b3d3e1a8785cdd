"""Loads and force elements that act on a structure's dofs beside the joints."""
