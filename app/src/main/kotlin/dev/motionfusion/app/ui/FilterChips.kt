package dev.motionfusion.app.ui

import android.view.View
import com.google.android.material.R as MaterialR
import com.google.android.material.chip.Chip
import com.google.android.material.chip.ChipDrawable
import com.google.android.material.chip.ChipGroup

/**
 * Replaces the group's chips by one checkable Material filter chip per item of [items], tagged with the item and
 * labelled by [label], at least 48 dp tall (the touch target): the settings' choices and the session detail's formats.
 */
internal fun <T : Any> ChipGroup.replaceFilterChips(items: List<T>, label: (T) -> CharSequence) {
    removeAllViews()
    for (item in items) {
        addView(Chip(context).apply {
            setChipDrawable(ChipDrawable.createFromAttributes(context, null, 0, MaterialR.style.Widget_Material3_Chip_Filter))
            id = View.generateViewId()
            tag = item
            text = label(item)
            isCheckable = true
            minHeight = (48 * resources.displayMetrics.density).toInt()
        })
    }
}
