from paintapp.cli import console

console()
