package dev.motionfusion.app.settings

import android.os.Bundle
import android.view.LayoutInflater
import android.view.View
import android.widget.LinearLayout
import android.widget.TextView
import androidx.activity.OnBackPressedCallback
import androidx.activity.viewModels
import androidx.appcompat.app.AlertDialog
import androidx.appcompat.app.AppCompatActivity
import androidx.lifecycle.Lifecycle
import androidx.lifecycle.lifecycleScope
import androidx.lifecycle.repeatOnLifecycle
import dev.motionfusion.app.R
import com.google.android.material.dialog.MaterialAlertDialogBuilder
import dev.motionfusion.app.ui.fitToSystemBars
import kotlinx.coroutines.launch

/**
 * Every setting, built from [Setting.ALL] (fusion-core's filter settings table and the app's own
 * few): a card per [Section], in two columns in landscape and on tablets. Edits change the
 * [SettingsViewModel]'s draft (kept across rotation); "Apply" persists it and hands it to the live
 * filter and the recorder at once (a recording keeps its own until it ends); "Defaults" puts every
 * value back to its default, each row's "Reset" its own. Leaving (Back, the app bar's Up) with
 * changes not applied asks first: Apply, Discard, or Cancel (stay) ([askBeforeLeaving]).
 */
class SettingsActivity : AppCompatActivity() {
    private val model: SettingsViewModel by viewModels {
        SettingsViewModel.Factory((application as SettingsRepository.Provider).settingsRepository)
    }
    private val rows = ArrayList<SettingRow>()
    private lateinit var message: TextView

    /** Back while the draft differs from the settings in force: asks instead of dropping the changes. */
    private val leaving = object : OnBackPressedCallback(false) {
        override fun handleOnBackPressed() = askBeforeLeaving()
    }

    /** The question on screen, for tests. */
    internal var dialog: AlertDialog? = null
        private set

    override fun onCreate(savedInstanceState: Bundle?) {
        super.onCreate(savedInstanceState)
        setContentView(R.layout.activity_settings)
        fitToSystemBars(findViewById(R.id.settings_root))
        setSupportActionBar(findViewById(R.id.toolbar))
        supportActionBar?.setDisplayHomeAsUpEnabled(true)
        message = findViewById(R.id.settings_message)
        buildSections(findViewById(R.id.settings_sections), resources.getBoolean(R.bool.settings_two_columns))
        findViewById<View>(R.id.apply).setOnClickListener { model.apply() }
        findViewById<View>(R.id.reset).setOnClickListener { model.resetAll() }
        onBackPressedDispatcher.addCallback(this, leaving)
        show(model.state.value)
        lifecycleScope.launch {
            repeatOnLifecycle(Lifecycle.State.STARTED) { model.state.collect { show(it) } }
        }
    }

    override fun onSupportNavigateUp(): Boolean {
        onBackPressedDispatcher.onBackPressed()
        return true
    }

    /** Apply (then leave), Discard (then leave), or Cancel (stay, the changes kept). */
    private fun askBeforeLeaving() {
        dialog = MaterialAlertDialogBuilder(this)
            .setTitle(R.string.settings_leave_title)
            .setMessage(R.string.settings_leave_text)
            .setPositiveButton(R.string.settings_apply) { _, _ ->
                model.apply()
                finish()
            }
            .setNegativeButton(R.string.settings_leave_discard) { _, _ ->
                model.discard()
                finish()
            }
            .setNeutralButton(R.string.settings_leave_cancel, null)
            .show()
    }

    /** The row of the setting stored under [key], for tests. */
    internal fun row(key: String): View = rows.first { it.setting.key == key }.view

    /** A card per non-empty section, in order; with [twoColumns] the cards alternate between two columns balanced by rows. */
    private fun buildSections(container: LinearLayout, twoColumns: Boolean) {
        val columns = List(if (twoColumns) 2 else 1) {
            LinearLayout(this).apply { orientation = LinearLayout.VERTICAL }.also { c ->
                container.addView(c, LinearLayout.LayoutParams(0, LinearLayout.LayoutParams.WRAP_CONTENT, 1f).apply { if (it == 1) marginStart = dp(12) })
            }
        }
        val load = IntArray(columns.size)
        for (section in Section.entries) {
            val settings = Setting.ALL.filter { it.section == section }
            if (settings.isEmpty()) continue
            val target = load.indices.minByOrNull { load[it] }!!
            val card = LayoutInflater.from(this).inflate(R.layout.settings_section, columns[target], false)
            card.findViewById<TextView>(R.id.section_title).setText(title(section))
            val list = card.findViewById<LinearLayout>(R.id.section_rows)
            for (s in settings) {
                val row = SettingRow(s, list, model::set, model::switch)
                list.addView(row.view)
                rows += row
            }
            columns[target].addView(card)
            load[target] += settings.size + 2
        }
    }

    private fun show(state: SettingsUiState) {
        for (row in rows) row.show(state.draft, state.errors[row.setting.key])
        message.text = when {
            state.errors.isNotEmpty() -> getString(R.string.settings_invalid)
            state.changed -> getString(R.string.settings_unsaved)
            state.justApplied -> getString(R.string.settings_saved)
            else -> ""
        }
        findViewById<View>(R.id.apply).isEnabled = state.changed
        leaving.isEnabled = state.changed
    }

    private fun title(s: Section): Int = when (s) {
        Section.GAINS -> R.string.settings_section_gains
        Section.REJECTION -> R.string.settings_section_rejection
        Section.BIAS -> R.string.settings_section_bias
        Section.LOW_PASS -> R.string.settings_section_low_pass
        Section.SATURATION -> R.string.settings_section_saturation
        Section.RECORDING -> R.string.settings_section_recording
        Section.RECORDED_SENSORS -> R.string.settings_section_recorded_sensors
        Section.CALIBRATION -> R.string.settings_section_calibration
        Section.DISPLAY -> R.string.settings_section_display
    }

    private fun dp(v: Int) = (v * resources.displayMetrics.density).toInt()
}
