"""The ``attneave`` commands about shapes: thin modules that parse
arguments, call one library function and print."""
