import time, sys
from problems import budding
ea, eb = float(sys.argv[1]), float(sys.argv[2])
t=time.time()
I = budding.first_instability(ea, eb)
print(ea, eb, I, I.stop, time.time()-t)
for p,w,low in I.scan[-3:]: print(round(p,3), {n: round(v,5) for n,v in low.items() if n<=12})
