//! Every formula of the seed notes on torque-free rotation, with the exact
//! Unicode it renders to. The English note gives the LaTeX source; the
//! worked examples of the Hinglish note only survive as rendered text, so
//! their LaTeX is written the way the note shows them.

use super::math_to_unicode;

#[track_caller]
fn renders(latex: &str, expected: &str) {
    match math_to_unicode(latex) {
        Ok(got) => assert_eq!(got, expected, "rendering {latex}"),
        Err(e) => panic!("{latex} did not render: {e} at {}", e.offset),
    }
}

#[test]
fn body_frame_and_inertia_tensor() {
    renders(r"\mathbf I", "I");
    renders(
        r"\mathbf I = \mathrm{diag}(I_1,I_2,I_3)",
        "I = diag(I₁, I₂, I₃)",
    );
    renders(
        r"\mathbf I=\mathrm{diag}(I_1,I_2,I_3)",
        "I = diag(I₁, I₂, I₃)",
    );
    renders(r"I_1,I_2,I_3", "I₁, I₂, I₃");
    renders(r"\vec L=\mathbf I\vec\omega", "L⃗ = Iω⃗");
}

#[test]
fn newton_euler_in_the_space_frame() {
    renders(
        r"\left(\frac{d\vec L}{dt}\right)_{\text{space}} = \vec N \quad(\text{external torque})",
        "(dL⃗/dt)_(space) = N⃗  (external torque)",
    );
}

#[test]
fn transport_theorem() {
    renders(
        r"\left(\frac{d\vec L}{dt}\right)_{\text{body}} + \vec\omega\times\vec L = \vec N",
        "(dL⃗/dt)_(body) + ω⃗ × L⃗ = N⃗",
    );
    renders(
        r"(d\vec A/dt)_{\text{space}} = (d\vec A/dt)_{\text{body}} + \vec\omega\times\vec A",
        "(dA⃗/dt)_(space) = (dA⃗/dt)_(body) + ω⃗ × A⃗",
    );
    renders(r"\vec\omega\times\vec L", "ω⃗ × L⃗");
}

#[test]
fn body_principal_frame_components() {
    renders(r"\vec L", "L⃗");
    renders(r"L_i = I_i\,\omega_i", "Lᵢ = Iᵢ ωᵢ");
    renders(r"I_i", "Iᵢ");
    renders(
        r"\left(\frac{d\vec L}{dt}\right)_{\text{body}} = (I_1\dot\omega_1,\, I_2\dot\omega_2,\, I_3\dot\omega_3)",
        "(dL⃗/dt)_(body) = (I₁ω̇₁, I₂ω̇₂, I₃ω̇₃)",
    );
    renders(
        r"\vec\omega=(\omega_1,\omega_2,\omega_3)",
        "ω⃗ = (ω₁, ω₂, ω₃)",
    );
    renders(
        r"\vec L=(I_1\omega_1,I_2\omega_2,I_3\omega_3)",
        "L⃗ = (I₁ω₁, I₂ω₂, I₃ω₃)",
    );
}

#[test]
fn cross_product_component() {
    renders(
        r"(\vec\omega\times\vec L)_1 = \omega_2 L_3 - \omega_3 L_2 = (I_3-I_2)\,\omega_2\omega_3",
        "(ω⃗ × L⃗)₁ = ω₂L₃ − ω₃L₂ = (I₃ − I₂) ω₂ω₃",
    );
}

#[test]
fn torque_free_euler_equations() {
    renders(r"\vec N=0", "N⃗ = 0");
    renders(
        r"I_1\dot\omega_1 = (I_2-I_3)\,\omega_2\omega_3",
        "I₁ω̇₁ = (I₂ − I₃) ω₂ω₃",
    );
    renders(
        r"I_1\dot\omega_1=(I_2-I_3)\omega_2\omega_3",
        "I₁ω̇₁ = (I₂ − I₃)ω₂ω₃",
    );
    renders(r"I_i\dot\omega_i", "Iᵢω̇ᵢ");
}

#[test]
fn energy_conservation_proof() {
    renders(
        r"\dfrac{dT}{dt} = I_1\omega_1\dot\omega_1 + I_2\omega_2\dot\omega_2 + I_3\omega_3\dot\omega_3",
        "dT/dt = I₁ω₁ω̇₁ + I₂ω₂ω̇₂ + I₃ω₃ω̇₃",
    );
    renders(
        r"= \omega_1\omega_2\omega_3\big[(I_2-I_3)+(I_3-I_1)+(I_1-I_2)\big] = 0.",
        "= ω₁ω₂ω₃[(I₂ − I₃) + (I₃ − I₁) + (I₁ − I₂)] = 0.",
    );
    renders(
        r"dT/dt=\omega_1\omega_2\omega_3[(I_2-I_3)+(I_3-I_1)+(I_1-I_2)]=0",
        "dT/dt = ω₁ω₂ω₃[(I₂ − I₃) + (I₃ − I₁) + (I₁ − I₂)] = 0",
    );
}

#[test]
fn conserved_scalars_and_ellipsoids() {
    renders(r"\omega", "ω");
    renders(r"\vec\omega", "ω⃗");
    renders(r"2T=", "2T =");
    renders(r"L^2=", "L² =");
    renders(r"2T=\sum I_i\omega_i^2", "2T = ∑ Iᵢωᵢ²");
    renders(r"L^2=\sum I_i^2\omega_i^2", "L² = ∑ Iᵢ²ωᵢ²");
}

#[test]
fn asymmetric_top_ordering() {
    renders(r"I_1 < I_2 < I_3", "I₁ < I₂ < I₃");
    renders(r"I_1<I_2<I_3", "I₁ < I₂ < I₃");
    renders(r"I", "I");
}

#[test]
fn spin_about_axis_three() {
    renders(r"\omega_3\approx\Omega", "ω₃ ≈ Ω");
    renders(r"\omega_1,\omega_2", "ω₁, ω₂");
    renders(
        r"\dot\omega_1 = \frac{I_2-I_3}{I_1}\Omega\,\omega_2,\qquad \dot\omega_2 = \frac{I_3-I_1}{I_2}\Omega\,\omega_1",
        "ω̇₁ = ((I₂ − I₃)/I₁)Ω ω₂,    ω̇₂ = ((I₃ − I₁)/I₂)Ω ω₁",
    );
    renders(
        r"\Rightarrow \ddot\omega_1 = \frac{(I_2-I_3)(I_3-I_1)}{I_1 I_2}\Omega^2\,\omega_1",
        "⇒ ω̈₁ = ((I₂ − I₃)(I₃ − I₁)/(I₁I₂))Ω² ω₁",
    );
    renders(r"\ddot\omega_1 = k\,\omega_1", "ω̈₁ = k ω₁");
}

#[test]
fn stability_signs() {
    renders(r"(I_2-I_3)<0", "(I₂ − I₃) < 0");
    renders(r"(I_3-I_1)>0", "(I₃ − I₁) > 0");
    renders(r"k<0", "k < 0");
    renders(r"(I_3-I_2)>0", "(I₃ − I₂) > 0");
    renders(r"(I_2-I_1)>0", "(I₂ − I₁) > 0");
    renders(r"k>0", "k > 0");
}

#[test]
fn growth_criterion() {
    renders(r"\ddot\omega_1=k\omega_1", "ω̈₁ = kω₁");
    renders(
        r"k=\frac{(I_b-I_c)(I_c-I_a)}{I_aI_b}\Omega^2",
        "k = ((I_b − I_c)(I_c − Iₐ)/(IₐI_b))Ω²",
    );
    renders(r"(I_a-I_b)(I_b-I_c)", "(Iₐ − I_b)(I_b − I_c)");
}

#[test]
fn symmetric_top() {
    renders(r"I_1=I_2", "I₁ = I₂");
    renders(r"I_1 = I_2 \equiv I_\perp \neq I_3", "I₁ = I₂ ≡ I_⟂ ≠ I₃");
    renders(
        r"I_3\dot\omega_3 = (I_1-I_2)\,\omega_1\omega_2 = 0 \to \omega_3 = \text{const}",
        "I₃ω̇₃ = (I₁ − I₂) ω₁ω₂ = 0 → ω₃ = const",
    );
    renders(
        r"\dot\omega_1 = \frac{I_\perp-I_3}{I_\perp}\omega_3\,\omega_2 \equiv -\Omega_b\,\omega_2,\quad \dot\omega_2 = +\Omega_b\,\omega_1",
        "ω̇₁ = ((I_⟂ − I₃)/I_⟂)ω₃ ω₂ ≡ −Ω_b ω₂,  ω̇₂ = +Ω_b ω₁",
    );
}

#[test]
fn body_precession_rate() {
    renders(
        r"\Omega_b=\dfrac{I_3-I_\perp}{I_\perp}\,\omega_3",
        "Ω_b = ((I₃ − I_⟂)/I_⟂) ω₃",
    );
    renders(
        r"\Omega_b = \frac{I_3-I_\perp}{I_\perp}\omega_3",
        "Ω_b = ((I₃ − I_⟂)/I_⟂)ω₃",
    );
    renders(r"\omega_3", "ω₃");
}

#[test]
fn sphere_check() {
    renders(r"I_1 = I_2 = I_3", "I₁ = I₂ = I₃");
    renders(r"\text{RHS} = 0", "RHS = 0");
    renders(r"\dot{\vec\omega} = 0", "ω⃗̇ = 0");
}

#[test]
fn worked_example_three() {
    renders(
        r"I_1 = 1,\ I_2 = 2,\ I_3 = 3\ (\text{kg·m}^2)",
        "I₁ = 1, I₂ = 2, I₃ = 3 (kg·m²)",
    );
    renders(r"\Omega = 10\ \text{rad/s}", "Ω = 10 rad/s");
    renders(
        r"k = \frac{(I_3-I_2)(I_2-I_1)}{I_1I_3}\Omega^2 = \frac{(1)(1)}{3}\cdot 100 = 33.3 > 0",
        "k = ((I₃ − I₂)(I₂ − I₁)/(I₁I₃))Ω² = (1)(1)/3 ⋅ 100 = 33.3 > 0",
    );
    renders(
        r"k>0 \Rightarrow \text{growth rate } \sqrt{k}\approx 5.8\ \text{s}^{-1}",
        "k > 0 ⇒ growth rate √k ≈ 5.8 s⁻¹",
    );
    renders(r"1/\sqrt{k} \approx 0.17\ \text{s}", "1/√k ≈ 0.17 s");
}
