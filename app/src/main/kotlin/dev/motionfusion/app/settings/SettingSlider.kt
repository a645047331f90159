package dev.motionfusion.app.settings

import android.view.View
import android.widget.TextView
import com.google.android.material.slider.Slider
import dev.motionfusion.app.R
import dev.motionfusion.app.live.LiveSettings
import dev.motionfusion.core.filter.FilterSettingDescriptor
import dev.motionfusion.core.filter.FilterSettingDescriptors
import java.math.BigDecimal
import java.math.RoundingMode
import java.util.Locale

/**
 * A numeric filter setting shown as a Material slider (layout settings_slider): the unit and the
 * default come from fusion-core's settings table, so the screen cannot drift from the filter's
 * settings; the range of the slider is the app's ([Range]: what is useful to sweep by hand,
 * widened to hold a stored value beyond it). [text] is the value as the form holds it: what was
 * shown unless the slider moved since, then the slider's value at [Range.decimals] places.
 */
internal class SettingSlider(root: View, private val range: Range, name: String, help: String) {
    /** The setting's slider range, in its unit. */
    class Range(val setting: String, val to: Double, val decimals: Int) {
        val descriptor: FilterSettingDescriptor = requireNotNull(FilterSettingDescriptors.named(setting)) { "no filter setting $setting" }
    }

    val slider: Slider = root.findViewById(R.id.setting_slider)
    private val value: TextView = root.findViewById(R.id.setting_value)
    private val help: TextView = root.findViewById(R.id.setting_help)
    private val unit = range.descriptor.unit
    private var exact = ""
    private var showing = false

    init {
        val d = range.descriptor
        root.findViewById<TextView>(R.id.setting_name).text = name
        val default = format(d.value(LiveSettings.DEFAULT_FILTER) as Double)
        this.help.text = root.context.getString(R.string.settings_default, withUnit(default), help)
        slider.valueFrom = 0f
        slider.valueTo = range.to.toFloat()
        slider.setLabelFormatter { withUnit(format(it.toDouble())) }
        slider.contentDescription = name
        slider.addOnChangeListener { _, v, _ ->
            if (!showing) exact = format(v.toDouble())
            value.text = withUnit(exact)
        }
    }

    var text: String
        get() = exact
        set(t) {
            exact = t.trim()
            val v = exact.replace(',', '.').toDoubleOrNull()
            if (v != null && v.isFinite() && v >= 0.0) {
                showing = true
                if (v > slider.valueTo) slider.valueTo = v.toFloat()
                slider.value = v.toFloat()
                showing = false
            }
            value.text = withUnit(exact)
        }

    /** Why the value is refused (null: accepted), shown under the slider. */
    var error: String?
        get() = help.error?.toString()
        set(e) { help.error = e }

    private fun format(v: Double): String = BigDecimal(v).setScale(range.decimals, RoundingMode.HALF_EVEN).stripTrailingZeros().toPlainString()

    private fun withUnit(v: String) = if (unit.isEmpty()) v else String.format(Locale.ROOT, "%s %s", v, unit)

    companion object {
        /** β up to 0.5 rad/s (the default 0.03; above 0.5 the accelerometer's noise comes through). */
        val BETA = Range("beta", 0.5, 3)

        /** ζ up to 0.05 (the default 0: off). */
        val ZETA = Range("zeta", 0.05, 4)
    }
}
