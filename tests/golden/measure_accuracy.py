"""The accuracy table of every system measure against its exact value.

Runs `flipcard sim --scene ID --measure M` on the scenes of
tests/decks/valid/measures-exact (Kepler e = 0.9, a rosette orbit, the
gated apsidal angle, coupled oscillators) and prints a Markdown table of
measured against exact values (closed forms, Kepler's equation, mpmath).
tests/measure_accuracy.rs asserts the same at 1e-6; this prints the numbers.

    python3 tests/golden/measure_accuracy.py target/release/flipcard
"""
import subprocess, sys, math
B=sys.argv[1]; import os; D=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "decks", "valid", "measures-exact", "decks")
PI=math.pi; GM=4*PI*PI
def run(scene, ms):
    out=[]
    for m in ms:
        p=subprocess.run([B,"sim","--decks",D,"--scene",scene,"--measure",m],capture_output=True,text=True)
        out.append(float(p.stdout.strip()) if p.returncode==0 else None)
    return out
import mpmath as mp
e=0.9
t_of=lambda E:(E-e*math.sin(E))/(2*PI)
r0=0.1; v0=2*PI*math.sqrt(19); h=r0*v0; c=0.05*h*h; En=(h*h-c)/(2*r0*r0)-GM/r0; a=-GM/(2*En); Tr=2*PI*math.sqrt(a**3/GM)
w1=1.0; w2=math.sqrt(1.2); Dl=(w2-w1)/2; S=(w2+w1)/2
mp.mp.dps=30
x1=lambda t: mp.cos(Dl*t)*mp.cos(S*t); x2=lambda t: mp.sin(Dl*t)*mp.sin(S*t)
def ext(f,sgn):
    best=None
    for i in range(40001):
        t=200.0*i/40000; v=sgn*float(f(t))
        if best is None or v>best[1]: best=(t,v)
    t=mp.findroot(lambda t: mp.diff(f,t), best[0]); return float(f(t))
cases=[
 ("kepler","max(r)",1.9),("kepler","min(speed)",math.sqrt(GM*(1-e)/(1+e))),("kepler","period(r)",1.0),("kepler","period(x)",1.0),
 ("kepler","mean(r)",1+e*e/2),("kepler","amplitude(r)",0.9),("kepler","time_of(x < 0)",t_of(math.acos(e))),("kepler","time_of(r = 1)",t_of(PI/2)),
 ("kepler-perturbed","max(r)",2*a-r0),("kepler-perturbed","period(r)",Tr),
 ("rosette-apsis","max(apsis)",180/math.sqrt(0.95)),("rosette-apsis","time_of(vr < 0)",Tr/2),
 ("coupled","min(x1)",ext(x1,-1)),("coupled","max(x2)",ext(x2,1)),("coupled","beat(x1)",PI/Dl),("coupled","beat(x2)",PI/Dl),("coupled","beat(e1)",PI/Dl),("coupled","beat(v1)",PI/Dl),
]
print("| scene | measure | exact | measured | relative error |")
print("|---|---|---|---|---|")
for sc,m,ex in cases:
    v=run(sc,[m])[0]
    if v is None: print(f"| {sc} | `{m}` | {ex:.10g} | refused | — |"); continue
    print(f"| {sc} | `{m}` | {ex:.10g} | {v:.10g} | {abs(v-ex)/abs(ex):.1e} |")
