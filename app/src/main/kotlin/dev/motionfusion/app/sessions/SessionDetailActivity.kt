package dev.motionfusion.app.sessions

import android.app.Activity
import android.content.ActivityNotFoundException
import android.content.Context
import android.content.Intent
import android.net.Uri
import android.widget.CheckBox
import androidx.activity.result.contract.ActivityResultContract
import com.google.android.material.chip.Chip
import com.google.android.material.chip.ChipGroup
import dev.motionfusion.app.export.ExportKind
import com.google.android.material.progressindicator.LinearProgressIndicator
import android.os.Bundle
import android.text.InputType
import android.view.View
import android.widget.Button
import android.widget.EditText
import android.widget.TextView
import androidx.appcompat.app.AlertDialog
import androidx.appcompat.app.AppCompatActivity
import androidx.activity.viewModels
import androidx.lifecycle.Lifecycle
import androidx.lifecycle.lifecycleScope
import androidx.lifecycle.repeatOnLifecycle
import com.google.android.material.dialog.MaterialAlertDialogBuilder
import dev.motionfusion.app.R
import dev.motionfusion.app.platform.Failure
import dev.motionfusion.app.sensor.WakeLockNeed
import dev.motionfusion.core.session.WakeLockUse
import dev.motionfusion.app.export.Exporter
import dev.motionfusion.app.ui.AnglePlotView
import dev.motionfusion.app.ui.Formats
import dev.motionfusion.app.ui.RateBarsView
import dev.motionfusion.app.ui.RatePlotView
import dev.motionfusion.app.ui.replaceFilterChips
import dev.motionfusion.app.ui.fitToSystemBars
import dev.motionfusion.app.ui.stackWhenCrowded
import kotlinx.coroutines.launch
import java.io.File

/**
 * One session, from [SessionDetailViewModel]: its summary (start, duration, size, per-stream
 * samples and achieved rates), a plot of the fused orientation's angles with the session's
 * markers, each stream's rate over time, rename, delete (after confirmation) and export
 * (Downloads, Save as…, Share) in the format chosen on it ([ExportKind]: the session's zip or what
 * `fusion export` writes, a still recording's noise model; the heading zeroed at the start on request).
 */
class SessionDetailActivity : AppCompatActivity() {
    private val deps by lazy { (application as SessionsDependencies.Provider).sessionsDependencies }
    private val model: SessionDetailViewModel by viewModels {
        SessionDetailViewModel.Factory(deps, intent.getStringExtra(EXTRA_SESSION) ?: "")
    }

    /** The dialog on screen (rename or delete), for tests. */
    internal var dialog: AlertDialog? = null
        private set

    override fun onCreate(savedInstanceState: Bundle?) {
        super.onCreate(savedInstanceState)
        setContentView(R.layout.activity_session_detail)
        fitToSystemBars(findViewById(R.id.detail_root))
        setSupportActionBar(findViewById(R.id.toolbar))
        supportActionBar?.setDisplayHomeAsUpEnabled(true)
        if (intent.getStringExtra(EXTRA_SESSION).isNullOrEmpty()) {
            finish()
            return
        }
        stackWhenCrowded(findViewById(R.id.detail_save_row))
        stackWhenCrowded(findViewById(R.id.detail_manage_row))
        findViewById<Button>(R.id.detail_rename).setOnClickListener { askRename() }
        findViewById<Button>(R.id.detail_delete).setOnClickListener { askDelete() }
        findViewById<Button>(R.id.detail_downloads).apply {
            visibility = if (Exporter.downloadsAvailable) View.VISIBLE else View.GONE
            setOnClickListener {
                val choice = model.state.value.choice
                export { app, dir, progress -> app.getString(R.string.export_done_downloads, Exporter.toDownloads(app, dir, choice, progress)) }
            }
        }
        findViewById<Button>(R.id.detail_save_as).setOnClickListener {
            try {
                val kind = model.state.value.choice.kind
                saveAs.launch(kind.mime to kind.fileName(model.name))
            } catch (e: ActivityNotFoundException) {
                model.message(getString(R.string.export_failed, getString(Failure.of(e, "opening another app").text)))
            }
        }
        findViewById<Button>(R.id.detail_share).setOnClickListener { share() }
        findViewById<Button>(R.id.detail_export_cancel).setOnClickListener { model.cancelExport() }
        findViewById<ChipGroup>(R.id.detail_formats).setOnCheckedStateChangeListener { group, ids ->
            if (showingChoice) return@setOnCheckedStateChangeListener
            val kind = ids.firstOrNull()?.let { group.findViewById<Chip>(it) }?.tag as? ExportKind ?: return@setOnCheckedStateChangeListener
            model.choose(model.state.value.choice.copy(kind = kind))
        }
        findViewById<CheckBox>(R.id.detail_zero_heading).setOnCheckedChangeListener { _, checked ->
            if (!showingChoice) model.choose(model.state.value.choice.copy(zeroHeading = checked))
        }
        lifecycleScope.launch {
            repeatOnLifecycle(Lifecycle.State.STARTED) { model.state.collect { show(it) } }
        }
        // Opened by the record bar's Share: the share starts once (not again after a rotation).
        if (savedInstanceState == null && intent.getBooleanExtra(EXTRA_SHARE, false)) share()
    }

    private fun share() {
        val choice = model.state.value.choice
        export { app, dir, progress -> Exporter.shareIntent(app, dir, choice, progress) }
    }

    override fun onSupportNavigateUp(): Boolean {
        finish()
        return true
    }

    /**
     * Shows [state]: the summary, the fused angles with the markers (timestamps on the session's
     * sensor clock) on the plot, each stream's rate over time, its samples and achieved rate.
     */
    internal fun show(state: SessionDetailUiState) {
        if (state.deleted) {
            finish()
            return
        }
        findViewById<TextView>(R.id.detail_name).text = state.name
        title = state.name
        findViewById<TextView>(R.id.detail_message).apply {
            text = state.message ?: ""
            visibility = if (state.message == null) View.GONE else View.VISIBLE
        }
        showChoice(state)
        showExport(state)
        val whenText = findViewById<TextView>(R.id.detail_when)
        val s = state.summary
        when {
            state.error != null -> whenText.text = getString(R.string.session_unreadable, state.error)
            s == null -> whenText.setText(R.string.session_loading)
            else -> {
                whenText.text = SessionsActivity.describe(this, s, state.recordingNow)
                val lines = s.streams.map {
                    getString(
                        R.string.session_stream_line, SessionsActivity.streamName(this, it.name),
                        Formats.isolated(this, "%,d", it.rows), Formats.isolated(this, "%.1f", it.rateHz),
                    )
                } +
                    getString(R.string.session_fused_line, Formats.isolated(this, "%,d", s.fusedRows))
                findViewById<TextView>(R.id.detail_streams).text = lines.joinToString("\n")
                findViewById<TextView>(R.id.detail_wake_lock).apply {
                    text = s.wakeLock?.let { wakeLockText(it) }
                    visibility = if (s.wakeLock == null) View.GONE else View.VISIBLE
                }
                findViewById<RateBarsView>(R.id.detail_rates).setBars(s.streams.filter { it.rows > 0 }.map { RateBarsView.Bar(SessionsActivity.shortName(this, it.name), it.rateHz) })
            }
        }
        state.rates?.let { r ->
            findViewById<RatePlotView>(R.id.detail_rate_plot).setLanes(r.ratesHz.map { (name, rates) -> RatePlotView.Lane(SessionsActivity.shortName(this, name), rates) }, r.binSeconds)
        }
        val angles = state.angles
        findViewById<AnglePlotView>(R.id.detail_plot).apply {
            emptyText = getString(if (state.loading) R.string.session_loading else R.string.session_plot_empty)
            if (angles != null) showSeries(angles.originNs, angles.timeS, angles.azimuthDeg, angles.pitchDeg, angles.rollDeg, angles.markers)
            contentDescription = getString(if (angles == null || angles.size == 0) R.string.session_plot_empty else R.string.session_plot_title)
        }
    }

    /** meta.json's `wake_lock` in the user's words: let go, or held and which streams forced it (docs/RECORDING.md, "Wake lock"). */
    private fun wakeLockText(w: WakeLockUse): String {
        val streams = w.forcedBy.joinToString(" · ") { SessionsActivity.streamName(this, it.key) } // names hold commas
        return when {
            !w.held -> getString(R.string.session_wake_lock_released)
            streams.isEmpty() -> getString(R.string.session_wake_lock_held)
            w.reason == WakeLockNeed.NOT_WAKE_UP.key -> getString(R.string.session_wake_lock_not_wake_up, streams)
            w.reason == WakeLockNeed.FIFO_TOO_SMALL.key -> getString(R.string.session_wake_lock_fifo_too_small, streams)
            else -> getString(R.string.session_wake_lock_held)
        }
    }

    /**
     * Runs [action] on the session's folder through the ViewModel (disk executor, folder lock,
     * progress, Cancel); it gets the application's context, never this activity's (it outlives a rotation).
     */
    private fun export(action: (Context, File, Exporter.Progress) -> Any) {
        val app = applicationContext
        model.export({ failure -> app.getString(R.string.export_failed, app.getString(failure.text)) }, getString(R.string.export_cancelled)) { dir, progress -> action(app, dir, progress) }
    }

    /** The chips of the kinds shown (the noise model only for a still recording), while [showChoice] sets them. */
    private var shownKinds: List<ExportKind> = emptyList()
    private var showingChoice = false

    /** The export format chips, what the chosen one holds, and the heading tare (orientation formats only). */
    private fun showChoice(state: SessionDetailUiState) {
        showingChoice = true
        try {
            val group = findViewById<ChipGroup>(R.id.detail_formats)
            val kinds = ExportKind.entries.filter { it != ExportKind.NOISE || state.summary?.stillRecording == true || state.choice.kind == it }
            if (kinds != shownKinds) {
                group.replaceFilterChips(kinds) { getString(it.label) }
                shownKinds = kinds
            }
            val choice = state.choice
            for (i in 0 until group.childCount) {
                val chip = group.getChildAt(i) as Chip
                if (chip.tag == choice.kind && !chip.isChecked) group.check(chip.id)
                chip.isEnabled = state.exporting == null
            }
            findViewById<TextView>(R.id.detail_format_about).setText(ABOUT.getValue(choice.kind))
            val tare = choice.kind.hasOrientation
            findViewById<CheckBox>(R.id.detail_zero_heading).apply {
                isChecked = choice.zeroHeading && tare
                isEnabled = tare && state.exporting == null
            }
            findViewById<TextView>(R.id.detail_zero_heading_hint).setText(if (tare) R.string.export_zero_heading_hint else R.string.export_zero_heading_na)
        } finally {
            showingChoice = false
        }
    }

    /** An export under way: its progress and Cancel, the export buttons off; a share's chooser started once. */
    private fun showExport(state: SessionDetailUiState) {
        val exporting = state.exporting
        findViewById<View>(R.id.detail_export_row).visibility = if (exporting == null) View.GONE else View.VISIBLE
        for (id in intArrayOf(R.id.detail_share, R.id.detail_downloads, R.id.detail_save_as, R.id.detail_rename, R.id.detail_delete)) {
            findViewById<View>(id).isEnabled = exporting == null
        }
        // Its error colour does not dim by itself when disabled.
        findViewById<View>(R.id.detail_delete).alpha = if (exporting == null) 1f else 0.38f
        if (exporting != null) {
            val percent = (100 * exporting).toInt()
            findViewById<LinearProgressIndicator>(R.id.detail_export_progress).setProgressCompat(percent, false)
            findViewById<TextView>(R.id.detail_export_text).text = getString(R.string.export_progress, percent)
        }
        state.share?.let {
            model.shareStarted()
            try {
                startActivity(it)
            } catch (e: ActivityNotFoundException) {
                model.message(getString(R.string.export_failed, getString(Failure.of(e, "opening another app").text)))
            }
        }
    }

    /** Save as…: the system's document picker creates the export's document (its type and name), then it is written there. */
    private val saveAs = registerForActivityResult(CreateExportDocument()) { uri ->
        if (uri != null) {
            val choice = model.state.value.choice
            export { app, dir, progress ->
                Exporter.toDocument(app, dir, uri, choice, progress)
                app.getString(R.string.export_done_document)
            }
        }
    }

    /** ACTION_CREATE_DOCUMENT for (MIME type, file name). */
    private class CreateExportDocument : ActivityResultContract<Pair<String, String>, Uri?>() {
        override fun createIntent(context: Context, input: Pair<String, String>): Intent =
            Intent(Intent.ACTION_CREATE_DOCUMENT).addCategory(Intent.CATEGORY_OPENABLE).setType(input.first).putExtra(Intent.EXTRA_TITLE, input.second)

        override fun parseResult(resultCode: Int, intent: Intent?): Uri? = intent.takeIf { resultCode == Activity.RESULT_OK }?.data
    }

    private fun askRename() {
        val input = EditText(this).apply {
            setText(model.name)
            setSelection(text.length)
            hint = getString(R.string.session_rename_hint)
            inputType = InputType.TYPE_CLASS_TEXT
            id = R.id.detail_rename_input
        }
        dialog = MaterialAlertDialogBuilder(this)
            .setTitle(R.string.session_rename)
            .setView(input)
            .setNegativeButton(R.string.cancel, null)
            .setPositiveButton(R.string.ok) { _, _ -> rename(input.text.toString()) }
            .show()
    }

    internal fun rename(newName: String) =
        model.rename(newName, getString(R.string.session_rename_invalid)) { getString(R.string.session_rename_failed, getString(it.text)) }

    private fun askDelete() {
        dialog = MaterialAlertDialogBuilder(this)
            .setMessage(getString(R.string.session_delete_confirm, model.name))
            .setNegativeButton(R.string.cancel, null)
            .setPositiveButton(R.string.session_delete) { _, _ -> model.delete { getString(R.string.session_delete_failed, getString(it.text)) } }
            .show()
    }

    internal companion object {
        const val EXTRA_SESSION = "dev.motionfusion.app.sessions.SESSION"
        const val EXTRA_SHARE = "dev.motionfusion.app.sessions.SHARE"

        /** What each format holds, under the chips. */
        val ABOUT = mapOf(
            ExportKind.SESSION to R.string.export_about_session,
            ExportKind.EUROC to R.string.export_about_euroc,
            ExportKind.KALIBR to R.string.export_about_kalibr,
            ExportKind.ROS2 to R.string.export_about_ros2,
            ExportKind.GCSV to R.string.export_about_gcsv,
            ExportKind.NOISE to R.string.export_about_noise,
        )

        /** The detail of the session folder [name]; [share]: its Share started as it opens. */
        fun intent(context: Context, name: String, share: Boolean = false): Intent =
            Intent(context, SessionDetailActivity::class.java).putExtra(EXTRA_SESSION, name).putExtra(EXTRA_SHARE, share)
    }
}
