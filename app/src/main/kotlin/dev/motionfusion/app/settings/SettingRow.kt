package dev.motionfusion.app.settings

import android.view.LayoutInflater
import android.view.View
import android.view.ViewGroup
import android.widget.Button
import android.widget.CompoundButton
import android.widget.LinearLayout
import android.widget.TextView
import com.google.android.material.chip.Chip
import com.google.android.material.chip.ChipGroup
import com.google.android.material.slider.Slider
import dev.motionfusion.app.R
import dev.motionfusion.app.ui.replaceFilterChips
import dev.motionfusion.app.ui.stackWhenCrowded
import dev.motionfusion.app.sensor.GyroSaturation
import dev.motionfusion.app.ui.Formats
import dev.motionfusion.core.settings.FilterSettingDescriptors
import dev.motionfusion.core.settings.SettingKind
import java.math.BigDecimal
import java.math.RoundingMode
import kotlin.math.ceil
import kotlin.math.log10

/**
 * The views of one [Setting], made from its description alone: a number is a slider with its
 * unit (angles also in degrees), its default and a reset button, with a switch beside it when 0
 * turns it off; a flag is a switch; a choice is a row of chips. User changes go to [onChange]
 * (value) and [onSwitch] (a number's on/off); [show] sets the views from settings without
 * calling back.
 */
internal class SettingRow(
    val setting: Setting,
    parent: ViewGroup,
    private val onChange: (Setting, Any) -> Unit,
    private val onSwitch: (Setting, Boolean) -> Unit,
) {
    val view: View = LayoutInflater.from(parent.context).inflate(
        when (setting.kind) {
            SettingKind.NUMBER -> R.layout.settings_slider
            SettingKind.BOOLEAN -> R.layout.settings_switch
            SettingKind.CHOICE -> R.layout.settings_choice
        },
        parent, false,
    )
    private val context = parent.context
    private val help: TextView = view.findViewById(R.id.setting_help)
    private val switch: CompoundButton? = view.findViewById(R.id.setting_switch)
    private val slider: Slider? = view.findViewById(R.id.setting_slider)
    private val value: TextView? = view.findViewById(R.id.setting_value)
    private val reset: Button? = view.findViewById(R.id.setting_reset)
    private val chips: ChipGroup? = view.findViewById(R.id.setting_choices)
    private val decimals = setting.range?.let { (3 - ceil(log10(it.endInclusive)).toInt()).coerceIn(0, 5) } ?: 0
    private var showing = false
    private var shownChoices: List<String> = emptyList()

    init {
        view.tag = setting.key
        view.findViewById<LinearLayout>(R.id.setting_head)?.let(::stackWhenCrowded)
        // Every row has the same view ids: the draft in the ViewModel, not view state, survives a rotation.
        view.isSaveFromParentEnabled = false
        val title = SettingText.title(context, setting)
        view.findViewById<TextView>(R.id.setting_name)?.text = title
        when (setting.kind) {
            SettingKind.NUMBER -> {
                val r = requireNotNull(setting.range) { "${setting.key} has no range" }
                val s = slider!!
                s.valueFrom = r.start.toFloat()
                s.valueTo = r.endInclusive.toFloat()
                s.contentDescription = title
                s.setLabelFormatter { withUnit(it.toDouble()) }
                s.addOnChangeListener { _, v, _ -> if (!showing) onChange(setting, round(v.toDouble())) }
                val d = setting.default as Double
                val helpText = when {
                    setting.key == GYRO_SATURATION_KEY -> R.string.settings_default_gyro_range // FusionPipeline: the range stands in for the default
                    setting.zeroDisables -> R.string.settings_default_off
                    else -> R.string.settings_default
                }
                val shownDefault = if (setting.zeroDisables && d == 0.0) context.getString(R.string.settings_off) else withUnit(d)
                help.text = context.getString(helpText, shownDefault, Math.round(GyroSaturation.MARGIN * 100).toInt())
                reset!!.setOnClickListener { onChange(setting, setting.default) }
                reset.contentDescription = context.getString(R.string.settings_reset_description, title)
                if (setting.zeroDisables) {
                    switch!!.visibility = View.VISIBLE
                    switch.contentDescription = title
                    switch.setOnCheckedChangeListener { _, on -> if (!showing) onSwitch(setting, on) }
                }
            }
            SettingKind.BOOLEAN -> {
                switch!!.text = title
                switch.setOnCheckedChangeListener { _, on -> if (!showing) onChange(setting, on) }
                help.text = SettingText.help(context, setting) ?: context.getString(R.string.settings_default, context.getString(if (setting.default == true) R.string.settings_on else R.string.settings_off))
            }
            SettingKind.CHOICE -> {
                help.text = context.getString(R.string.settings_default, SettingText.label(context, setting, setting.default as String))
                chips!!.setOnCheckedStateChangeListener { group, ids ->
                    if (showing) return@setOnCheckedStateChangeListener
                    val chip = ids.firstOrNull()?.let { group.findViewById<Chip>(it) } ?: return@setOnCheckedStateChangeListener
                    onChange(setting, chip.tag as String)
                }
            }
        }
    }

    /** Shows the value of this setting in [s] and [error] (null: none; else shown as refused, the detail in its words). */
    fun show(s: LiveSettings, error: String?) {
        showing = true
        try {
            when (setting.kind) {
                SettingKind.NUMBER -> showNumber(setting.value(s) as Double)
                SettingKind.BOOLEAN -> switch!!.isChecked = setting.value(s) as Boolean
                SettingKind.CHOICE -> showChoice(s)
            }
            help.error = error?.let { context.getString(R.string.settings_refused, it) }
        } finally {
            showing = false
        }
    }

    private fun showNumber(v: Double) {
        val s = slider!!
        // A stored value beyond the slider's span widens it rather than being clipped.
        if (v < s.valueFrom) s.valueFrom = v.toFloat()
        if (v > s.valueTo) s.valueTo = v.toFloat()
        s.value = v.toFloat()
        val off = setting.zeroDisables && v == 0.0
        switch?.isChecked = !off
        s.isEnabled = !off
        value!!.text = if (off) context.getString(R.string.settings_off) else withUnit(v)
        reset!!.isEnabled = v != setting.default
    }

    private fun showChoice(s: LiveSettings) {
        val group = chips!!
        val choices = setting.choicesFor(s)
        if (choices != shownChoices) {
            group.replaceFilterChips(choices) { SettingText.label(context, setting, it) }
            shownChoices = choices
        }
        val current = setting.value(s) as String
        for (i in 0 until group.childCount) {
            val chip = group.getChildAt(i) as Chip
            if (chip.tag == current) group.check(chip.id)
        }
    }

    private fun round(v: Double): Double = BigDecimal(v).setScale(decimals, RoundingMode.HALF_EVEN).toDouble()

    /** "0.052 rad/s (3.0°/s)": the value at the row's precision with its unit, in the locale's format; angles also in degrees. */
    fun withUnit(v: Double): String {
        val text = Formats.number(context, v, decimals)
        val unit = setting.unit
        if (unit.isEmpty()) return text
        if (!unit.startsWith("rad")) return context.getString(R.string.value_with_unit, text, unit)
        return context.getString(R.string.value_with_degrees, text, unit, String.format(Formats.locale(context), "%.1f", Math.toDegrees(v)), unit.removePrefix("rad"))
    }
}

/** The gyroscope saturation setting's key: its default is replaced by the phone's range. */
private val GYRO_SATURATION_KEY = FilterSettingDescriptors.named("gyroSaturation")!!.jsonKey
