package dev.motionfusion.app.settings

import android.os.Bundle
import android.view.View
import android.widget.CompoundButton
import android.widget.EditText
import android.widget.RadioGroup
import android.widget.TextView
import androidx.appcompat.app.AppCompatActivity
import dev.motionfusion.app.R
import dev.motionfusion.app.live.AngleConvention
import dev.motionfusion.app.live.LiveSettings
import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.app.ui.fitToSystemBars

/**
 * Filter, display and rate settings. β and ζ are sliders whose name, unit and default come from
 * fusion-core's settings table ([SettingSlider]); the flags are switches; "Apply" validates the
 * form ([SettingsForm], with the core's own checks), marks the fields in error, or persists the
 * settings and hands them to the live filter at once (a recording keeps its own until it ends); "Defaults" shows the defaults.
 */
class SettingsActivity : AppCompatActivity() {
    private lateinit var settings: SettingsRepository
    private lateinit var beta: SettingSlider
    private lateinit var zeta: SettingSlider
    private lateinit var rateHz: EditText
    private lateinit var message: TextView

    override fun onCreate(savedInstanceState: Bundle?) {
        super.onCreate(savedInstanceState)
        setContentView(R.layout.activity_settings)
        fitToSystemBars(findViewById(R.id.settings_root))
        setSupportActionBar(findViewById(R.id.toolbar))
        supportActionBar?.setDisplayHomeAsUpEnabled(true)
        settings = (application as SettingsRepository.Provider).settingsRepository
        beta = SettingSlider(findViewById(R.id.beta_setting), SettingSlider.BETA, getString(R.string.settings_beta), getString(R.string.settings_beta_help))
        zeta = SettingSlider(findViewById(R.id.zeta_setting), SettingSlider.ZETA, getString(R.string.settings_zeta), getString(R.string.settings_zeta_help))
        rateHz = findViewById(R.id.rate_hz_value)
        message = findViewById(R.id.settings_message)
        // A restored instance keeps what the user set; a new one shows the settings in force.
        if (savedInstanceState == null) showForm(SettingsForm.of(settings.settings.value))
        findViewById<RadioGroup>(R.id.rate).setOnCheckedChangeListener { _, id -> rateHz.isEnabled = id == R.id.rate_hz }
        rateHz.isEnabled = findViewById<RadioGroup>(R.id.rate).checkedRadioButtonId == R.id.rate_hz
        findViewById<View>(R.id.apply).setOnClickListener { apply() }
        findViewById<View>(R.id.reset).setOnClickListener {
            showForm(SettingsForm.of(LiveSettings()))
            message.text = ""
        }
    }

    override fun onSupportNavigateUp(): Boolean {
        finish()
        return true
    }

    /** Validates and applies the form; true when the settings were saved. */
    fun apply(): Boolean {
        return when (val r = readForm().parse()) {
            is SettingsForm.Result.Invalid -> {
                beta.error = r.errors[SettingsField.BETA]
                zeta.error = r.errors[SettingsField.ZETA]
                rateHz.error = r.errors[SettingsField.RATE_HZ]
                message.setText(R.string.settings_invalid)
                false
            }
            is SettingsForm.Result.Valid -> {
                beta.error = null; zeta.error = null; rateHz.error = null
                settings.update(r.settings)
                message.setText(R.string.settings_saved)
                true
            }
        }
    }

    private fun showForm(f: SettingsForm) {
        beta.text = f.beta
        zeta.text = f.zeta
        switch(R.id.nine_d).isChecked = f.nineD
        switch(R.id.rest_bias).isChecked = f.restBias
        switch(R.id.mag_rejection).isChecked = f.magRejection
        switch(R.id.acc_rejection).isChecked = f.accRejection
        findViewById<RadioGroup>(R.id.convention).check(
            if (f.convention == AngleConvention.ANDROID) R.id.convention_android else R.id.convention_aerospace,
        )
        findViewById<RadioGroup>(R.id.rate).check(
            when (f.delay) {
                SamplingRate.Delay.FASTEST -> R.id.rate_fastest
                SamplingRate.Delay.GAME -> R.id.rate_game
                SamplingRate.Delay.UI -> R.id.rate_ui
                SamplingRate.Delay.NORMAL -> R.id.rate_normal
                null -> R.id.rate_hz
            },
        )
        rateHz.setText(f.rateHz)
    }

    private fun readForm(): SettingsForm = SettingsForm(
        beta = beta.text,
        zeta = zeta.text,
        nineD = switch(R.id.nine_d).isChecked,
        restBias = switch(R.id.rest_bias).isChecked,
        magRejection = switch(R.id.mag_rejection).isChecked,
        accRejection = switch(R.id.acc_rejection).isChecked,
        convention = if (findViewById<RadioGroup>(R.id.convention).checkedRadioButtonId == R.id.convention_aerospace) {
            AngleConvention.AEROSPACE
        } else {
            AngleConvention.ANDROID
        },
        delay = when (findViewById<RadioGroup>(R.id.rate).checkedRadioButtonId) {
            R.id.rate_fastest -> SamplingRate.Delay.FASTEST
            R.id.rate_game -> SamplingRate.Delay.GAME
            R.id.rate_ui -> SamplingRate.Delay.UI
            R.id.rate_normal -> SamplingRate.Delay.NORMAL
            else -> null
        },
        rateHz = rateHz.text.toString(),
    )

    private fun switch(id: Int): CompoundButton = findViewById(id)
}
