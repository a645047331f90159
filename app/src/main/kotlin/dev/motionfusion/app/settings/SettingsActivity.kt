package dev.motionfusion.app.settings

import android.os.Bundle
import android.view.LayoutInflater
import android.view.View
import android.widget.LinearLayout
import android.widget.TextView
import androidx.activity.viewModels
import androidx.appcompat.app.AppCompatActivity
import androidx.core.view.ViewCompat
import androidx.lifecycle.Lifecycle
import androidx.lifecycle.lifecycleScope
import androidx.lifecycle.repeatOnLifecycle
import dev.motionfusion.app.R
import com.google.android.material.button.MaterialButton
import com.google.android.material.snackbar.BaseTransientBottomBar
import com.google.android.material.snackbar.Snackbar
import dev.motionfusion.app.ui.fitToSystemBars
import kotlinx.coroutines.launch

/**
 * Every setting, built from [Setting.ALL] (fusion-core's filter settings table and the app's own
 * few): a card per [Section], in two columns in landscape and on tablets; recording, the sensors recorded,
 * calibration and display first, the filter's tuning under "Advanced", collapsed until opened. Each change applies at
 * once ([SettingsViewModel]: persisted, handed to the live filter and the recorder; a recording keeps its own until it
 * ends) and a snackbar offers to undo it; "Defaults" puts every value back to its default, each row's "Reset" its
 * own, both undoable the same way. Leaving asks nothing: every change is already in force, and a refused value is
 * never in the settings (its row says why).
 */
class SettingsActivity : AppCompatActivity() {
    private val model: SettingsViewModel by viewModels {
        SettingsViewModel.Factory((application as SettingsRepository.Provider).settingsRepository)
    }
    private val rows = ArrayList<SettingRow>()
    private lateinit var message: TextView
    private lateinit var advanced: View
    private lateinit var advancedToggle: MaterialButton

    /** The change whose Undo is on screen (its id), so that each change gets one snackbar. */
    private var undoShown = 0

    /** The snackbar offering Undo, for tests. */
    internal var snackbar: Snackbar? = null
        private set

    override fun onCreate(savedInstanceState: Bundle?) {
        super.onCreate(savedInstanceState)
        setContentView(R.layout.activity_settings)
        fitToSystemBars(findViewById(R.id.settings_root))
        setSupportActionBar(findViewById(R.id.toolbar))
        supportActionBar?.setDisplayHomeAsUpEnabled(true)
        message = findViewById(R.id.settings_message)
        val twoColumns = resources.getBoolean(R.bool.settings_two_columns)
        buildSections(findViewById(R.id.settings_sections), Section.entries.filter { !it.advanced }, twoColumns)
        buildSections(findViewById(R.id.settings_advanced), Section.entries.filter { it.advanced }, twoColumns)
        advanced = findViewById(R.id.settings_advanced)
        advancedToggle = findViewById(R.id.settings_advanced_toggle)
        advancedToggle.setOnClickListener { showAdvanced(advanced.visibility != View.VISIBLE) }
        showAdvanced(savedInstanceState?.getBoolean(ADVANCED_OPEN) == true)
        findViewById<View>(R.id.reset).setOnClickListener { model.resetAll() }
        // A snackbar already offered before a rotation is not offered again.
        undoShown = savedInstanceState?.getInt(UNDO_SHOWN) ?: 0
        show(model.state.value)
        lifecycleScope.launch {
            repeatOnLifecycle(Lifecycle.State.STARTED) { model.state.collect { show(it) } }
        }
    }

    override fun onSaveInstanceState(outState: Bundle) {
        super.onSaveInstanceState(outState)
        outState.putBoolean(ADVANCED_OPEN, advanced.visibility == View.VISIBLE)
        outState.putInt(UNDO_SHOWN, undoShown)
    }

    override fun onSupportNavigateUp(): Boolean {
        onBackPressedDispatcher.onBackPressed()
        return true
    }

    /** The filter's tuning shown ([open]) or folded away, the toggle's arrow and its spoken state with it. */
    private fun showAdvanced(open: Boolean) {
        advanced.visibility = if (open) View.VISIBLE else View.GONE
        advancedToggle.setIconResource(if (open) R.drawable.ic_expand_less else R.drawable.ic_expand_more)
        ViewCompat.setStateDescription(advancedToggle, getString(if (open) R.string.settings_advanced_open else R.string.settings_advanced_closed))
    }

    /** The last change applied, with Undo: once per change. */
    private fun offerUndo(u: Undo?) {
        if (u == null || u.id == undoShown) return
        undoShown = u.id
        val text = u.key?.let { k -> rows.firstOrNull { it.setting.key == k } }
            ?.let { getString(R.string.settings_changed, SettingText.title(this, it.setting)) }
            ?: getString(R.string.settings_defaults_applied)
        snackbar = Snackbar.make(findViewById(R.id.settings_root), text, Snackbar.LENGTH_LONG)
            .setAction(R.string.settings_undo) { model.undo() }
            .addCallback(object : BaseTransientBottomBar.BaseCallback<Snackbar>() {
                override fun onDismissed(bar: Snackbar, event: Int) {
                    // Replaced by the next change's: that one carries the undo on.
                    if (event != DISMISS_EVENT_CONSECUTIVE && event != DISMISS_EVENT_ACTION) model.undoExpired(u.id)
                }
            })
            .also {
                // A long title at a large font: the whole text rather than Material's two lines cut short.
                it.view.findViewById<TextView>(com.google.android.material.R.id.snackbar_text)?.maxLines = 5
                it.show()
            }
    }

    /** The row of the setting stored under [key], for tests. */
    internal fun row(key: String): View = rows.first { it.setting.key == key }.view

    /** A card per non-empty section of [sections], in order; with [twoColumns] the cards alternate between two columns balanced by rows. */
    private fun buildSections(container: LinearLayout, sections: List<Section>, twoColumns: Boolean) {
        val columns = List(if (twoColumns) 2 else 1) {
            LinearLayout(this).apply { orientation = LinearLayout.VERTICAL }.also { c ->
                container.addView(c, LinearLayout.LayoutParams(0, LinearLayout.LayoutParams.WRAP_CONTENT, 1f).apply { if (it == 1) marginStart = dp(12) })
            }
        }
        val load = IntArray(columns.size)
        for (section in sections) {
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
        message.text = if (state.errors.isNotEmpty()) getString(R.string.settings_invalid) else ""
        offerUndo(state.undo)
    }

    private fun title(s: Section): Int = when (s) {
        Section.GAINS -> R.string.settings_section_gains
        Section.REJECTION -> R.string.settings_section_rejection
        Section.BIAS -> R.string.settings_section_bias
        Section.LOW_PASS -> R.string.settings_section_low_pass
        Section.SATURATION -> R.string.settings_section_saturation
        Section.RECORDING -> R.string.settings_section_recording
        Section.HEADING -> R.string.settings_section_heading
        Section.RECORDED_SENSORS -> R.string.settings_section_recorded_sensors
        Section.CALIBRATION -> R.string.settings_section_calibration
        Section.DISPLAY -> R.string.settings_section_display
    }

    private fun dp(v: Int) = (v * resources.displayMetrics.density).toInt()

    private companion object {
        const val ADVANCED_OPEN = "advanced_open"
        const val UNDO_SHOWN = "undo_shown"
    }
}
